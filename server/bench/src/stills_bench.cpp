#include "penumbra/bench/stills_bench.hpp"

#include <penumbra/bench/report.hpp>
#include <penumbra/encode/encode.hpp>
#include <penumbra/imageio/compare.hpp>

#include <fstream>
#include <memory>
#include <utility>

namespace penumbra::bench {
namespace {

struct Measured {
    base::ImageRgba8 image;
    double ms = 0.0;
    int steps = 0;
    double sample_distance = 0.0;
};

// The frames of one mode on the view `view`, in kStillFrames' order.
base::Result<std::array<Measured, kStillFrames.size()>> measure_mode(quality::AccuracyBench& bench,
                                                                     scene::FrameRequest view,
                                                                     const StillsConfig& config) {
    std::array<Measured, kStillFrames.size()> frames;
    view.settings.jitter = false;
    auto unjittered = bench.frame(view);
    if (!unjittered) {
        return unjittered.error();
    }
    frames[0] = {std::move(unjittered->image), unjittered->frame_ms, 0};
    view.settings.jitter = true;
    const scene::FrameRequest small = scene::interactive_request(view).first;
    auto interactive = bench.frame(small);
    if (!interactive) {
        return interactive.error();
    }
    auto shown = imageio::stretched(interactive->image, view.settings.width, view.settings.height);
    if (!shown) {
        return shown.error();
    }
    frames[1] = {std::move(*shown), interactive->frame_ms, 0, small.settings.sample_distance};
    auto still = bench.converged(view, config.max_steps, config.threshold);
    if (!still) {
        return still.error();
    }
    frames[2] = {std::move(still->still.image), still->still.frame_ms, 0};
    frames[3] = {std::move(still->last.image), still->last.frame_ms, still->steps};
    // A frame's cost grows with its samples, so each halving of the step doubles it.
    view.settings.jitter = false;
    for (double ms = frames[0].ms;
         2.0 * ms <= frames[3].ms &&
         view.settings.sample_distance / 2.0 >= scene::setting::sample_distance.min;
         ms *= 2.0) {
        view.settings.sample_distance /= 2.0;
    }
    auto same_time = bench.frame(view);
    if (!same_time) {
        return same_time.error();
    }
    frames[4] = {std::move(same_time->image), same_time->frame_ms, 0,
                 view.settings.sample_distance};
    return frames;
}

base::Status write_png(const std::filesystem::path& path, const base::ImageRgba8& image) {
    std::error_code ignored;
    std::filesystem::create_directories(path.parent_path(), ignored);
    return encode::write_image(path, image);
}

std::string row_text(const StillsRow& row) {
    char line[160];
    std::snprintf(line, sizeof line, "  %-11s %-20s %8s %8.4f %9.1f", scene::to_string(row.mode),
                  base::to_string(row.frame), psnr_text(row.errors.psnr).c_str(), row.errors.ssim,
                  row.ms);
    std::string text = line;
    if (row.frame == StillFrame::converged) {
        text += "  after " + std::to_string(row.steps) + " steps";
    }
    if (row.frame == StillFrame::unjittered_same_time) {
        text += "  at step " + distance_label(row.sample_distance);
    }
    return text + "\n";
}

// What no interactive frame can beat, whatever its mode and step: the truth rendered at the
// interactive frame's size, stretched back as the browser shows it.
base::Status print_interactive_ceiling(quality::AccuracyBench& bench, TruthCache& cache,
                                       const volume::Volume& volume,
                                       const scene::FrameRequest& view,
                                       const base::ImageRgbaF& exact, std::FILE* out) {
    const scene::FrameRequest small = scene::interactive_request(view).first;
    auto truth = cache.truth(bench, volume, small, kTruth);
    if (!truth) {
        return truth.error();
    }
    auto shown = imageio::stretched(truth->image, view.settings.width, view.settings.height);
    if (!shown) {
        return shown.error();
    }
    auto errors = quality::errors_against(exact, *shown);
    if (!errors) {
        return errors.error();
    }
    std::fprintf(out,
                 "  the truth at the interactive size (%dx%d), stretched: %s dB, SSIM %.4f (no "
                 "interactive frame of that size does better; truth %s)\n",
                 small.settings.width, small.settings.height, psnr_text(errors->psnr).c_str(),
                 errors->ssim, describe(*truth).c_str());
    return base::Ok{};
}

// One case: its truth, then every mode's frames, appended to `rows`.
base::Status measure_case(render::FrameRenderer& renderer, const StillsConfig& config,
                          const StillsCase& c, TruthCache& cache, std::vector<StillsRow>& rows,
                          std::FILE* out) {
    auto loaded = volume::load_volume(c.volume);
    if (!loaded) {
        return loaded.error();
    }
    const auto volume = std::make_shared<const volume::Volume>(std::move(*loaded));
    if (auto status = renderer.set_volume(volume); !status) {
        return status;
    }
    auto view = config.frame_for(*volume, c);
    if (!view) {
        return view.error();
    }
    quality::AccuracyBench bench(renderer, config.repeat);
    auto truth = cache.truth(bench, *volume, *view, kTruth);
    if (!truth) {
        return truth.error();
    }
    std::fprintf(out, "\ncase %s: %s, tf %s; truth %s\n", c.name.c_str(), volume->name.c_str(),
                 view->transfer_function.name.c_str(), describe(*truth).c_str());
    const base::ImageRgbaF exact = base::to_rgba_f(truth->image);
    if (auto status = print_interactive_ceiling(bench, cache, *volume, *view, exact, out);
        !status) {
        return status;
    }
    std::fprintf(out, "  %-11s %-20s %8s %8s %9s\n", "mode", "frame", "PSNR dB", "SSIM", "ms");
    std::fflush(out);
    if (config.images) {
        if (auto status = write_png(*config.images / (c.name + "_truth.png"), truth->image);
            !status) {
            return status;
        }
    }
    for (const scene::Mode mode : config.modes) {
        scene::FrameRequest request = *view;
        request.settings.mode = mode;
        auto frames = measure_mode(bench, request, config);
        if (!frames) {
            return frames.error();
        }
        for (std::size_t i = 0; i < kStillFrames.size(); ++i) {
            Measured& m = (*frames)[i];
            auto errors = quality::errors_against(exact, m.image);
            if (!errors) {
                return errors.error();
            }
            rows.push_back({c.name, mode, kStillFrames[i].value, *errors, m.ms, m.steps,
                            m.sample_distance > 0.0 ? m.sample_distance
                                                    : request.settings.sample_distance});
            std::fputs(row_text(rows.back()).c_str(), out);
            if (config.images) {
                const std::string name = c.name + "_" + scene::to_string(mode) + "_" +
                                         base::to_string(kStillFrames[i].value) + ".png";
                if (auto status = write_png(*config.images / name, m.image); !status) {
                    return status;
                }
            }
        }
        std::fflush(out);
    }
    return base::Ok{};
}

// Each target of the default mode, met or missed, by case.
void print_targets(const std::vector<StillsRow>& rows, std::FILE* out) {
    const scene::Mode mode = scene::starting_frame({}).settings.mode;
    std::fprintf(out, "\ntargets of the default mode (%s):\n", scene::to_string(mode));
    for (const StillsTarget& target : kStillsTargets) {
        for (const StillsRow& row : rows) {
            if (row.mode != mode || row.frame != target.frame ||
                (!target.case_name.empty() && row.case_name != target.case_name)) {
                continue;
            }
            std::fprintf(out, "  %-15s %-12s >= %4.1f dB: %s (%s dB, %+.1f)\n",
                         row.case_name.c_str(), base::to_string(row.frame), target.psnr,
                         row.errors.psnr >= target.psnr ? "met" : "missed",
                         psnr_text(row.errors.psnr).c_str(), row.errors.psnr - target.psnr);
        }
    }
}

}  // namespace

base::Result<std::vector<StillsRow>> bench_stills(render::FrameRenderer& renderer,
                                                  const StillsConfig& config, TruthCache& cache,
                                                  std::FILE* out) {
    std::fprintf(out,
                 "penumbra bench stills: every mode's frames against the converged truth (%s); "
                 "refinement stops at a change of %g levels or %d steps\n",
                 describe(kTruth).c_str(), config.threshold, config.max_steps);
    std::vector<StillsRow> rows;
    for (const StillsCase& c : config.cases) {
        if (auto status = measure_case(renderer, config, c, cache, rows, out); !status) {
            return status.error();
        }
    }
    print_targets(rows, out);
    return rows;
}

base::Status write_stills_csv(const std::vector<StillsRow>& rows,
                              const std::filesystem::path& path) {
    std::ofstream csv(path);
    csv << "case,mode,frame,psnr,ssim,rmse,ms,steps,sample_distance\n";
    for (const StillsRow& row : rows) {
        csv << row.case_name << ',' << scene::to_string(row.mode) << ','
            << base::to_string(row.frame) << ',' << psnr_text(row.errors.psnr) << ','
            << row.errors.ssim << ',' << row.errors.rmse << ',' << row.ms << ',' << row.steps << ','
            << row.sample_distance << '\n';
    }
    if (!csv) {
        return base::make_error(base::ErrorCode::io_error, "cannot write '" + path.string() + "'",
                                "--csv");
    }
    return base::Ok{};
}

}  // namespace penumbra::bench
