#include "penumbra/quality/startup.hpp"

#include <penumbra/base/data_dir.hpp>
#include <penumbra/imageio/imageio.hpp>
#include <penumbra/quality/table_json.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <utility>

namespace penumbra::quality {
namespace {

// "llvmpipe (LLVM 15.0.6, 256 bits)" -> "llvmpipe_LLVM_15.0.6_256_bits": a file name on any file
// system, still readable.
std::string file_name_of(const std::string& gl_renderer) {
    std::string name;
    for (const char c : gl_renderer) {
        if (std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '.' || c == '-') {
            name += c;
        } else if (!name.empty() && name.back() != '_') {
            name += '_';
        }
    }
    while (!name.empty() && name.back() == '_') {
        name.pop_back();
    }
    return name.empty() ? std::string("unknown") : name;
}

std::string format(const char* pattern, auto... values) {
    char text[512];
    std::snprintf(text, sizeof text, pattern, values...);
    return text;
}

std::string loaded_note(const Table& table, const std::filesystem::path& path) {
    return format("%zu measured points from %s", table.points.size(), path.c_str());
}

// The measured table as the server uses it, cached for the next start where there is a cache.
ServeTable adopt_measured(const StartupMeasurement& measured, const TablePaths& paths) {
    const StartupTable& startup = *measured.table;
    ServeTable result{std::make_shared<const Table>(startup.table), {}};
    const Table& table = *result.table;
    result.notes.push_back(format(
            "measured %zu points on %s at %dx%d in %.1f s (%s time)%s", table.points.size(),
            measured.volume.c_str(), table.width, table.height, startup.seconds, timing_name(table),
            startup.complete ? "" : "; stopped at the time limit, serving with those"));
    if (!paths.cache) {
        result.notes.emplace_back("not cached (neither XDG_CACHE_HOME nor HOME is set)");
    } else if (auto status = write_table_file(*paths.cache, table,
                                              choose_presets(table, default_budgets(table.points)),
                                              "quality cache");
               !status) {
        result.notes.push_back("not cached: " + status.error().to_string());
    } else {
        result.notes.push_back("cached in " + paths.cache->string() + " for the next start");
    }
    return result;
}

}  // namespace

StartupOptions startup_options() {
    StartupOptions options;
    Sweep& sweep = options.sweep;
    sweep.lights = {{10.0, 45.0}};
    sweep.modes = {scene::Mode::phong, scene::Mode::half_angle, scene::Mode::sbrc,
                   scene::Mode::sbrc_cone};
    sweep.slices = {64, 128, 256};
    sweep.resolutions = {128, 256};
    sweep.half_angle_slices = {64, 128};
    sweep.half_angle_resolutions = {128};
    sweep.distances = {1.0 / 256.0};
    sweep.repeat = 3;
    return options;
}

base::Result<StartupTable> measure_startup_table(
        render::FrameRenderer& renderer, const std::shared_ptr<const volume::Volume>& volume,
        scene::FrameRequest frame, const StartupOptions& options) {
    using Clock = std::chrono::steady_clock;
    const Clock::time_point start = Clock::now();
    const auto seconds = [&] {
        return std::chrono::duration<double>(Clock::now() - start).count();
    };
    if (options.side < min_image_side) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "SSIM needs images of at least " + std::to_string(min_image_side) +
                                        "x" + std::to_string(min_image_side),
                                "side");
    }
    frame.settings.width = options.side;
    frame.settings.height = options.side;
    frame.settings.phong = true;

    StartupTable result;
    result.table = make_table(renderer.info(), options.sweep.repeat, true);
    describe_frame(result.table, frame);
    if (auto status = renderer.set_volume(volume); !status) {
        return status.error();
    }
    AccuracyBench bench(renderer, options.sweep.repeat);
    const PointObserver within_limit = [&](const Point&) {
        return seconds() < options.time_limit_s;
    };
    for (const LightAngles& light : options.sweep.lights) {
        auto complete = measure_view(bench, options.sweep, frame, volume->name, light, within_limit,
                                     result.table.points);
        if (!complete) {
            return complete.error();
        }
        if (!*complete) {
            result.complete = false;
            break;
        }
    }
    result.seconds = seconds();
    return result;
}

TablePaths table_paths(const render::RendererInfo& info,
                       const std::optional<std::filesystem::path>& cache_dir) {
    TablePaths paths;
    const std::filesystem::path name = info.gpu_timer_queries ? "gpu.json" : "llvmpipe.json";
    paths.committed = base::data_dir("accuracy").value_or("share/penumbra/accuracy") / name;
    if (cache_dir) {
        paths.cache = *cache_dir / ("quality-" + file_name_of(info.renderer) + ".json");
    }
    return paths;
}

bool should_measure(Measure measure, const TablePaths& paths) {
    switch (measure) {
        case Measure::never:
            return false;
        case Measure::always:
            return true;
        case Measure::where_missing:
            return !std::filesystem::exists(paths.committed) &&
                   !(paths.cache && std::filesystem::exists(*paths.cache));
    }
    return false;
}

std::optional<std::string> startup_volume(const std::vector<std::string>& offered) {
    if (offered.empty()) {
        return std::nullopt;
    }
    const auto ch2 = std::find(offered.begin(), offered.end(), "ch2.nii.gz");
    return ch2 != offered.end() ? *ch2 : offered.front();
}

StartupMeasurement measure_at_startup(render::FrameRenderer& renderer, Measure measure,
                                      const OfferedVolumes& volumes, const FrameFor& frame_for,
                                      std::FILE* out) {
    StartupMeasurement result;
    if (!should_measure(measure, table_paths(renderer.info()))) {
        return result;
    }
    if (!imageio::available()) {
        result.error = base::make_error(base::ErrorCode::image_io_unavailable,
                                        "this penumbra was built without OpenImageIO, so it cannot "
                                        "compare the frames a quality table ranks",
                                        "quality table");
        return result;
    }
    const auto id = startup_volume(volumes.ids());
    if (!id) {
        result.error =
                base::make_error(base::ErrorCode::no_volume, "no volume to measure on", "--data");
        return result;
    }
    auto volume = volumes.acquire(*id);
    if (!volume) {
        result.error = volume.error();
        return result;
    }
    auto frame = frame_for(**volume);
    if (!frame) {
        result.error = frame.error();
        return result;
    }
    result.volume = *id;
    const StartupOptions options = startup_options();
    std::fprintf(out, "quality:  %s a short table on %s at %dx%d (at most ~%.0f s)\n",
                 measure == Measure::always ? "--quality-measure: measuring"
                                            : "no table for this device: measuring",
                 id->c_str(), options.side, options.side, options.time_limit_s);
    std::fflush(out);
    auto table = measure_startup_table(renderer, *volume, std::move(*frame), options);
    if (!table) {
        result.error = table.error();
        return result;
    }
    result.table = std::move(table.value());
    return result;
}

base::Result<ServeTable> serve_table(const std::optional<std::filesystem::path>& given,
                                     const StartupMeasurement& measured, const TablePaths& paths) {
    if (given) {
        auto table = read_table_file(*given);
        if (!table) {
            return table.error();
        }
        ServeTable result{std::make_shared<const Table>(std::move(table.value())), {}};
        result.notes.push_back(loaded_note(*result.table, *given));
        return result;
    }
    if (measured.table) {
        return adopt_measured(measured, paths);
    }
    ServeTable result;
    if (measured.error) {
        result.notes.push_back("nothing measured at start-up: " + measured.error->to_string());
    }
    const bool use_cache = !std::filesystem::exists(paths.committed) && paths.cache;
    const std::filesystem::path found = use_cache ? *paths.cache : paths.committed;
    auto table = read_table_file(found);
    if (!table && table.error().code == base::ErrorCode::not_found) {
        result.notes.push_back("no measured table for this device (" + paths.committed.string() +
                               "); frame budgets are ignored until `penumbra bench accuracy` "
                               "writes one");
    } else if (!table && use_cache) {
        result.notes.push_back("ignoring the cached table (" + table.error().to_string() +
                               "); remove it to measure again");
    } else if (!table) {
        return table.error();
    } else {
        result.table = std::make_shared<const Table>(std::move(table.value()));
        result.notes.push_back(loaded_note(*result.table, found));
    }
    return result;
}

}  // namespace penumbra::quality
