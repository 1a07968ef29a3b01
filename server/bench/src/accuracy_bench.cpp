#include "penumbra/bench/accuracy_bench.hpp"

#include <penumbra/bench/report.hpp>
#include <penumbra/bench/sweep.hpp>
#include <penumbra/imageio/imageio.hpp>
#include <penumbra/quality/table_json.hpp>

#include <algorithm>
#include <cmath>

namespace penumbra::bench {
namespace {

void print_timing(std::FILE* out, const render::RendererInfo& info, const quality::Sweep& sweep) {
    std::fprintf(out, "penumbra bench accuracy\ngl:       %s | %s | %s\n", info.renderer.c_str(),
                 info.version.c_str(), info.platform.c_str());
    if (info.gpu_timer_queries) {
        std::fprintf(out, "timing:   GPU timer queries, median of %d frame(s) after 1 warm-up\n",
                     sweep.repeat);
    } else {
        std::fprintf(out,
                     "timing:   wall clock (this GL's timer queries mean nothing: software "
                     "rasteriser),\n          median of %d frame(s) after 1 warm-up; lighter "
                     "defaults for a software rasteriser\n",
                     sweep.repeat);
    }
}

}  // namespace

base::Status bench_accuracy(render::Renderer& renderer, const quality::Sweep& sweep,
                            const quality::FrameFor& frame_for, TruthCache& truths,
                            quality::Table& table, std::FILE* out) {
    print_timing(out, renderer.info(), sweep);
    // Without comparison the frames are only timed (and written with --images), so no truth.
    TruthCache* const truth_source = imageio::available() ? &truths : nullptr;
    if (truth_source != nullptr) {
        const std::string kept = truths.folder() ? "in " + truths.folder()->string()
                                                 : std::string("for this run only");
        std::fprintf(out, "truth:    %s, kept %s\n", describe(kTruth).c_str(), kept.c_str());
    } else {
        std::fprintf(out,
                     "truth:    none: this penumbra was built without OpenImageIO and cannot "
                     "compare images; frames are timed, errors not measured (nan)%s\n",
                     sweep.images ? ", images written to compare elsewhere" : "");
    }
    if (sweep.images) {
        std::fprintf(out, "images:   %s\n", sweep.images->c_str());
    }
    const std::uint64_t frames =
            quality::frames_per_view(sweep) * sweep.lights.size() * sweep.volumes.size();
    const Progress progress(frames);
    std::fprintf(out,
                 "sweep:    %zu volume(s) x %zu light(s): %llu frames (progress shows the time "
                 "left)\n",
                 sweep.volumes.size(), sweep.lights.size(),
                 static_cast<unsigned long long>(frames));
    const SweepObserver print{
            .frame = [out](const quality::Table& t) { std::fputs(frame_text(t).c_str(), out); },
            .view =
                    [out](const std::string& volume, const quality::LightAngles& light) {
                        std::fputs(view_header(volume, light).c_str(), out);
                    },
            .point =
                    [out, &progress](const quality::Point& p, std::uint64_t done) {
                        std::fprintf(out, "%s  %s\n", point_row(p).c_str(), progress(done).c_str());
                        std::fflush(out);
                    },
            .truth =
                    [out](const TruthCache::Found& found) {
                        std::fprintf(out, "  truth %s\n", describe(found).c_str());
                        std::fflush(out);
                    }};
    return measure_sweep(renderer, sweep, frame_for, print, table, truth_source);
}

base::Status report_accuracy(const quality::Table& table, const AccuracyReport& report,
                             std::FILE* out) {
    // A build without image comparison measures times only (errors NaN): nothing to rank by.
    const bool compared = std::none_of(
            table.points.begin(), table.points.end(),
            [](const quality::Point& p) { return std::isnan(p.psnr) || std::isnan(p.psnr_truth); });
    if (!compared && (report.json || report.plot)) {
        return base::make_error(base::ErrorCode::image_io_unavailable,
                                "--json and --plot rank settings by their errors, which a penumbra "
                                "built without OpenImageIO cannot measure (--csv and --images can)",
                                report.json ? "--json" : "--plot");
    }
    std::vector<quality::Preset> presets;
    if (compared) {
        presets = quality::choose_presets(table, report.budgets_ms.empty()
                                                         ? quality::default_budgets(table.points)
                                                         : report.budgets_ms);
        std::fputs(presets_text(table, presets).c_str(), out);
    }
    if (report.csv) {
        if (auto status = write_csv(table, *report.csv, "--csv"); !status) {
            return status;
        }
        std::fprintf(out, "csv:      %s\n", report.csv->c_str());
    }
    if (report.json) {
        if (auto status = quality::write_table_file(*report.json, table, presets, "--json");
            !status) {
            return status;
        }
        std::fprintf(out, "json:     %s\n", report.json->c_str());
    }
    if (report.plot) {
        auto files = write_plot(table, *report.plot, "--plot");
        if (!files) {
            return files.error();
        }
        std::fprintf(out, "plot:     %s, %s (script %s)\n", files->png.c_str(), files->svg.c_str(),
                     files->script.c_str());
    }
    return base::Ok{};
}

base::Status report_accuracy_file(const std::string& path, const AccuracyReport& report,
                                  std::FILE* out) {
    auto table = quality::read_table_file(path);
    if (!table) {
        return table.error();
    }
    std::fprintf(out, "penumbra bench accuracy (from %s)\ngl:       %s | %s\npoints:   %zu\n",
                 path.c_str(), table->device.c_str(), table->gl_version.c_str(),
                 table->points.size());
    return report_accuracy(*table, report, out);
}

}  // namespace penumbra::bench
