#include "arguments.hpp"
#include "commands.hpp"
#include "render_options.hpp"

#include <penumbra/quality/mode_bench.hpp>
#include <penumbra/quality/optimisation_bench.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/camera.hpp>
#include <penumbra/volume/volume.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::app {
namespace {

using namespace quality;

constexpr scene::LightBufferBuilder builders[] = {scene::LightBufferBuilder::per_slice,
                                                  scene::LightBufferBuilder::multi_slice};

int fail(const base::Error& error) {
    return report_failure("bench", error);
}

int usage_error(const base::Error& error) {
    return report_usage_error("bench", error);
}

void print_bench_usage() {
    std::puts(
            "usage: penumbra bench <benchmark> [options]\n"
            "\n"
            "benchmarks:\n"
            "  modes    frame time of every rendering mode over slices x light-buffer resolution,\n"
            "           light-buffer reuse vs rebuild, and the two light-buffer builders\n"
            "  accuracy error vs the reference (RMSE, PSNR, SSIM) against frame time over\n"
            "           modes x slices x light-buffer resolution x sample distance; quality\n"
            "           presets per frame-time budget; CSV, JSON and a plot\n"
            "  refine   progressive stills: PSNR of each refinement step against a reference at\n"
            "           1/8 of the sample distance, next to the unjittered frame\n"
            "\n"
            "`penumbra bench <benchmark> --help` lists its options.");
}

void print_modes_usage() {
    std::printf(
            "usage: penumbra bench modes [options]\n"
            "\n"
            "Times each mode side by side in one run and prints the ratios that matter:\n"
            "half_angle vs sbrc at equal slices, sbrc's growth with slices, per_slice vs\n"
            "multi_slice builder, the local light lookup vs the paper's. Absolute times mean "
            "something only on a GPU; on a software\n"
            "rasteriser read the ratios.\n"
            "\n"
            "  --volume FILE                  (default %s)\n"
            "  --modes LIST                   modes to time, comma-separated (default: every\n"
            "                                 mode); the builder comparison runs when a sbrc\n"
            "                                 mode is listed\n"
            "  --slices-list N,...            light slices n to sweep (default 64,128,256)\n"
            "  --light-res-list R,...         light-buffer resolutions R to sweep (default\n"
            "                                 128,256,512)\n"
            "  --repeat N                     timed frames per point after 1 warm-up (default 5)\n"
            "  --volumes FILE,...             volumes for the optimisation table (default: the\n"
            "                                 --volume); the sweeps run on --volume\n"
            "  --gradients automatic|central|texture  where shaded samples get gradients:\n"
            "                                 central differences, the precomputed texture, or\n"
            "                                 the one measured faster on this kind of device\n"
            "                                 (default automatic)\n"
            "  --brick-voxels N               voxels per side of the bricks empty-space\n"
            "                                 skipping leaps over (default: the renderer's)\n"
            "  --optimisations-only           only the optimisation table: each mode's frame\n"
            "                                 time with and without empty-space skipping, the\n"
            "                                 PSNR between the two images, the light-buffer\n"
            "                                 build with and without, and phong with central\n"
            "                                 differences against the gradient texture\n"
            "  --csv FILE                     also write one row per point of the sweeps\n"
            "  --debug-gl                     GL debug output to the log\n"
            "\n"
            "frame options (as for `penumbra render`; --mode, --slices and --light-res are swept\n"
            "instead; --builder and --light-lookup pick what the sbrc modes use; the paper's\n"
            "method is --light-lookup interpolate --slab-samples 1):\n%s",
            default_volume_path, frame_options_help());
}

// "      12.345       n/a": wall then gpu milliseconds.
std::string cells(const Measurement& m) {
    char text[48];
    if (m.gpu_ms) {
        std::snprintf(text, sizeof text, "%12.3f %9.3f", m.wall_ms, *m.gpu_ms);
    } else {
        std::snprintf(text, sizeof text, "%12.3f %9s", m.wall_ms, "n/a");
    }
    return text;
}

// a / b on wall times, with the gpu ratio alongside where both have one.
std::string ratio(const Measurement* a, const Measurement* b) {
    if (a == nullptr || b == nullptr || b->wall_ms <= 0.0) {
        return "n/a";
    }
    char text[64];
    if (a->gpu_ms && b->gpu_ms && *b->gpu_ms > 0.0) {
        std::snprintf(text, sizeof text, "%.2f (gpu %.2f)", a->wall_ms / b->wall_ms,
                      *a->gpu_ms / *b->gpu_ms);
    } else {
        std::snprintf(text, sizeof text, "%.2f", a->wall_ms / b->wall_ms);
    }
    return text;
}

bool contains(const std::vector<scene::Mode>& modes, scene::Mode mode) {
    return std::find(modes.begin(), modes.end(), mode) != modes.end();
}

// One run of `bench modes`: what it sweeps, and its results so far.
struct ModesRun {
    ModeBench& bench;
    TimedResults& results;
    std::vector<scene::Mode> modes;
    std::vector<int> slices;
    std::vector<int> resolutions;
    std::string builder;  // the builder in use
    bool any_light_buffer_mode = false;

    [[nodiscard]] int middle_resolution() const { return resolutions[resolutions.size() / 2]; }

    base::Status record(TimedPoint point, const scene::FrameRequest& request, LightBufferUse use,
                        const std::string& pass) {
        auto measured = bench.measure(point, request, use, pass);
        if (!measured) {
            return measured.error();
        }
        point.measurement = *measured;
        results.add(point);
        return base::Ok{};
    }
};

// The modes without a light buffer: one frame series each, half_angle over the grid.
base::Status measure_frames(ModesRun& run) {
    std::printf("\nframe time (ms)\n  %-11s %5s %5s %12s %9s\n", "mode", "n", "R", "wall", "gpu");
    for (const scene::ModeInfo& row : scene::modes()) {
        const scene::Mode mode = row.mode;
        if (!contains(run.modes, mode) || mode == scene::Mode::half_angle ||
            scene::uses_light_buffer(mode)) {
            continue;
        }
        const TimedPoint point{mode, "frame", "", 0, 0, {}};
        if (auto status =
                    run.record(point, run.bench.request(mode, 0, 0), LightBufferUse::none, {});
            !status) {
            return status;
        }
        std::printf("  %-11s %5s %5s %s\n", scene::to_string(mode), "-", "-",
                    cells(*run.results.find(mode, "frame")).c_str());
        std::fflush(stdout);
    }
    if (contains(run.modes, scene::Mode::half_angle)) {
        for (const int n : run.slices) {
            for (const int r : run.resolutions) {
                const scene::Mode mode = scene::Mode::half_angle;
                const TimedPoint point{mode, "frame", "", n, r, {}};
                if (auto status = run.record(point, run.bench.request(mode, n, r),
                                             LightBufferUse::none, {});
                    !status) {
                    return status;
                }
                std::printf("  %-11s %5d %5d %s\n", scene::to_string(mode), n, r,
                            cells(*run.results.find(mode, "frame", n, r)).c_str());
                std::fflush(stdout);
            }
        }
    }
    return base::Ok{};
}

// The light-buffer modes: the buffer cached against rebuilt every frame.
base::Status measure_light_buffer_modes(ModesRun& run) {
    for (const scene::ModeInfo& row : scene::modes()) {
        const scene::Mode mode = row.mode;
        if (!scene::uses_light_buffer(mode) || !contains(run.modes, mode)) {
            continue;
        }
        if (!run.any_light_buffer_mode) {
            run.any_light_buffer_mode = true;
            std::printf(
                    "\nlight-buffer modes (ms): cached = buffer reused, only the camera moves; "
                    "rebuild = the light\nmoves %g deg every frame, so the buffer is rebuilt "
                    "(builder %s)\n",
                    light_nudge_degrees, run.builder.c_str());
            std::printf("  %-11s %5s %5s %12s %9s %12s %9s  %s\n", "mode", "n", "R", "cached wall",
                        "gpu", "rebuild wall", "gpu", "rebuild/cached");
        }
        for (const int n : run.slices) {
            for (const int r : run.resolutions) {
                const scene::FrameRequest request = run.bench.request(mode, n, r);
                const TimedPoint cached{mode, "cached", run.builder, n, r, {}};
                const TimedPoint rebuild{mode, "rebuild", run.builder, n, r, {}};
                if (auto status = run.record(cached, request, LightBufferUse::cached, {});
                    !status) {
                    return status;
                }
                if (auto status = run.record(rebuild, request, LightBufferUse::rebuild, {});
                    !status) {
                    return status;
                }
                const Measurement* c = run.results.find(mode, "cached", n, r);
                const Measurement* b = run.results.find(mode, "rebuild", n, r);
                std::printf("  %-11s %5d %5d %s %s  %s\n", scene::to_string(mode), n, r,
                            cells(*c).c_str(), cells(*b).c_str(), ratio(b, c).c_str());
                std::fflush(stdout);
            }
        }
    }
    return base::Ok{};
}

// The two builders: the light_buffer pass alone.
base::Status measure_builders(ModesRun& run) {
    if (run.any_light_buffer_mode) {
        std::printf(
                "\nlight-buffer builders (ms): the light_buffer pass alone, rebuilt every "
                "frame\n  %5s %5s %12s %9s %12s %9s  %s\n",
                "n", "R", "per_slice", "gpu", "multi_slice", "gpu", "per/multi");
        for (const int n : run.slices) {
            for (const int r : run.resolutions) {
                for (const auto builder : builders) {
                    scene::FrameRequest request = run.bench.request(scene::Mode::sbrc, n, r);
                    request.settings.light_buffer.builder = builder;
                    const std::string name = scene::to_string(builder);
                    const TimedPoint point{scene::Mode::sbrc, "light_buffer_pass", name, n, r, {}};
                    if (auto status = run.record(point, request, LightBufferUse::rebuild,
                                                 "light_buffer_" + name);
                        !status) {
                        return status;
                    }
                }
                const Measurement* per_slice =
                        run.results.find_builder(scene::LightBufferBuilder::per_slice, n, r);
                const Measurement* multi_slice =
                        run.results.find_builder(scene::LightBufferBuilder::multi_slice, n, r);
                std::printf("  %5d %5d %s %s  %s\n", n, r, cells(*per_slice).c_str(),
                            cells(*multi_slice).c_str(), ratio(per_slice, multi_slice).c_str());
                std::fflush(stdout);
            }
        }
    }
    return base::Ok{};
}

// The paper's interpolating light lookup against the local one.
base::Status measure_lookups(ModesRun& run) {
    const int r_mid = run.middle_resolution();
    if (contains(run.modes, scene::Mode::sbrc)) {
        std::printf(
                "\nlight lookups (ms): sbrc, light buffer cached, R=%d: the paper's interpolation "
                "between layers\nvs the local march through the last slab\n  %5s %12s %9s %12s "
                "%9s  %s\n",
                r_mid, "n", "interpolate", "gpu", "local", "gpu", "local/interpolate");
        for (const int n : run.slices) {
            for (const auto lookup : {scene::LightLookup::interpolate, scene::LightLookup::local}) {
                scene::FrameRequest request = run.bench.request(scene::Mode::sbrc, n, r_mid);
                request.settings.light_buffer.lookup = lookup;
                const TimedPoint point{scene::Mode::sbrc,
                                       std::string("lookup_") + scene::to_string(lookup),
                                       run.builder,
                                       n,
                                       r_mid,
                                       {}};
                if (auto status = run.record(point, request, LightBufferUse::cached, {}); !status) {
                    return status;
                }
            }
            const Measurement* interpolate =
                    run.results.find(scene::Mode::sbrc, "lookup_interpolate", n, r_mid);
            const Measurement* local =
                    run.results.find(scene::Mode::sbrc, "lookup_local", n, r_mid);
            std::printf("  %5d %s %s  %s\n", n, cells(*interpolate).c_str(), cells(*local).c_str(),
                        ratio(local, interpolate).c_str());
            std::fflush(stdout);
        }
    }
    return base::Ok{};
}

void print_ratios(const ModesRun& run) {
    const int r_mid = run.middle_resolution();
    const int n_min = *std::min_element(run.slices.begin(), run.slices.end());
    const int n_max = *std::max_element(run.slices.begin(), run.slices.end());
    std::printf("\nratios (of median wall times; gpu from timer queries where they work)\n");
    std::printf(
            "  half_angle / sbrc at equal n, R=%d (sbrc with its light buffer cached | "
            "rebuilt every frame | cached,\n  read with the paper's interpolating lookup):\n",
            r_mid);
    for (const int n : run.slices) {
        const Measurement* half_angle =
                run.results.find(scene::Mode::half_angle, "frame", n, r_mid);
        std::printf(
                "    n=%-5d cached %-22s rebuild %-22s interpolate %s\n", n,
                ratio(half_angle, run.results.find(scene::Mode::sbrc, "cached", n, r_mid)).c_str(),
                ratio(half_angle, run.results.find(scene::Mode::sbrc, "rebuild", n, r_mid)).c_str(),
                ratio(half_angle,
                      run.results.find(scene::Mode::sbrc, "lookup_interpolate", n, r_mid))
                        .c_str());
    }
    std::printf(
            "  cached frame time at n=%d / at n=%d, R=%d (the paper: it barely grows with n; "
            "GPU target <= 1.20\n  from 64 to 256):\n",
            n_max, n_min, r_mid);
    for (const scene::ModeInfo& row : scene::modes()) {
        const scene::Mode mode = row.mode;
        if (!scene::uses_light_buffer(mode)) {
            continue;
        }
        std::printf("    %-11s %s\n", scene::to_string(mode),
                    ratio(run.results.find(mode, "cached", n_max, r_mid),
                          run.results.find(mode, "cached", n_min, r_mid))
                            .c_str());
    }
    std::printf(
            "  builder per_slice / multi_slice, the light_buffer pass alone, R=%d (GPU target "
            ">= 10 at n=256):\n",
            r_mid);
    for (const int n : run.slices) {
        std::printf(
                "    n=%-5d %s\n", n,
                ratio(run.results.find_builder(scene::LightBufferBuilder::per_slice, n, r_mid),
                      run.results.find_builder(scene::LightBufferBuilder::multi_slice, n, r_mid))
                        .c_str());
    }
}

void print_modes_header(const render::RendererInfo& info, const volume::Volume& volume,
                        const ModeBench& bench, int repeat) {
    const scene::RenderSettings& s = bench.base().settings;
    std::printf("penumbra bench modes\n");
    std::printf("gl:       %s | %s | %s\n", info.renderer.c_str(), info.version.c_str(),
                info.platform.c_str());
    if (bench.gpu_timers()) {
        std::printf(
                "note:     absolute times mean something only on a GPU; compare the ratios "
                "across machines\n");
    } else {
        std::printf(
                "note:     software rasteriser (no GPU timer queries): absolute times mean "
                "something\n          only on a GPU; here read only the ratios\n");
    }
    std::printf("volume:   %s %ux%ux%u %s\n", volume.name.c_str(), volume.dims.x, volume.dims.y,
                volume.dims.z, volume::to_string(volume.type));
    std::printf(
            "frame:    %dx%d, tf %s, %s compositing, %s stage, sbrc builder %s, light lookup "
            "%s%s\n",
            s.width, s.height, bench.base().transfer_function.name.c_str(),
            scene::to_string(s.compositing), scene::to_string(s.stage),
            scene::to_string(s.light_buffer.builder), scene::to_string(s.light_buffer.lookup),
            s.phong ? ", phong" : "");
    std::printf(
            "timing:   per point 1 warm-up + %d timed frame(s), the camera orbiting %g deg a "
            "frame;\n          medians of the frame's summed pass wall_ms (gpu: summed timer "
            "queries)\n",
            repeat, orbit_step_degrees);
    std::fflush(stdout);
}

base::Status refuse_swept_options(const Arguments& a) {
    // These three are what the benchmark sweeps; accepting one would silently ignore it.
    const std::pair<const char*, const char*> swept[] = {
            {"mode", "--modes"}, {"slices", "--slices-list"}, {"light-res", "--light-res-list"}};
    for (const auto& [option, instead] : swept) {
        if (a.has(option)) {
            return base::make_error(
                    "invalid_argument",
                    std::string("bench modes sweeps this; use ") + instead + " LIST",
                    std::string("--") + option);
        }
    }
    return base::Ok{};
}

// What `bench modes` sweeps.
struct ModesSweep {
    std::vector<scene::Mode> modes;
    std::vector<int> slices;
    std::vector<int> resolutions;
    int repeat = 5;
};

base::Result<ModesSweep> modes_sweep(const Arguments& a) {
    auto slice_counts = parse_counts(a.get("slices-list").value_or("64,128,256"), "slices-list");
    auto resolutions =
            parse_counts(a.get("light-res-list").value_or("128,256,512"), "light-res-list");
    auto modes = parse_modes(a.get("modes").value_or(scene::mode_names(",")), "modes");
    auto repeat = a.integer("repeat", 5);
    if (!slice_counts || !resolutions || !modes || !repeat) {
        return !slice_counts  ? slice_counts.error()
               : !resolutions ? resolutions.error()
               : !modes       ? modes.error()
                              : repeat.error();
    }
    if (*repeat < 1 || *repeat > 1000) {
        return base::make_error("invalid_argument", "expects 1..1000", "--repeat");
    }
    return ModesSweep{*modes, *slice_counts, *resolutions, *repeat};
}

// The optimisation table's options.
struct OptimisationOptions {
    std::vector<std::string> volumes;
    render::GradientSource gradients = render::GradientSource::automatic;
    int brick_voxels = 0;  // 0: the renderer's default
    bool only = false;     // the table without the sweeps
};

std::optional<render::GradientSource> parse_gradient_source(const std::string& text) {
    if (text == "automatic") {
        return render::GradientSource::automatic;
    }
    if (text == "central") {
        return render::GradientSource::central_differences;
    }
    if (text == "texture") {
        return render::GradientSource::texture;
    }
    return std::nullopt;
}

base::Result<OptimisationOptions> optimisation_options(const Arguments& a,
                                                       const std::string& volume_path) {
    OptimisationOptions options;
    options.volumes = split_list(a.get("volumes").value_or(volume_path));
    if (options.volumes.empty()) {
        return base::make_error("invalid_argument", "expects FILE,...", "--volumes");
    }
    const auto gradients = parse_gradient_source(a.get("gradients").value_or("automatic"));
    if (!gradients) {
        return base::make_error("invalid_argument", "expects automatic, central or texture",
                                "--gradients");
    }
    options.gradients = *gradients;
    auto brick_voxels = a.integer("brick-voxels", 0);
    if (!brick_voxels) {
        return brick_voxels.error();
    }
    if (*brick_voxels < 0 || *brick_voxels > 256) {
        return base::make_error("invalid_argument",
                                "expects 1..256, or 0 for the renderer's default",
                                "--brick-voxels");
    }
    options.brick_voxels = *brick_voxels;
    options.only = a.has("optimisations-only");
    if (options.only && a.has("csv")) {
        return base::make_error("invalid_argument",
                                "the optimisation table writes no CSV; its rows are printed",
                                "--csv");
    }
    return options;
}

// A volume of the optimisation table with its frame, kept for the gradient comparison, which
// runs once the bench's renderer is gone.
struct TableVolume {
    std::shared_ptr<const volume::Volume> volume;
    scene::FrameRequest request;
};

// The optimisation table on each of its volumes; the renderer is left on the last of them.
base::Result<std::vector<TableVolume>> measure_optimisation_tables(
        const Arguments& a, render::Renderer& renderer, const ModesSweep& sweep,
        const OptimisationOptions& options, const std::shared_ptr<const volume::Volume>& main,
        const std::string& main_path) {
    std::vector<TableVolume> phong_cases;
    for (const std::string& path : options.volumes) {
        std::shared_ptr<const volume::Volume> table_volume = main;
        if (path != main_path) {
            auto loaded = volume::load_volume(path);
            if (!loaded) {
                return loaded.error();
            }
            table_volume = std::make_shared<const volume::Volume>(std::move(loaded.value()));
        }
        auto request = frame_request_from(a, *table_volume);
        if (!request) {
            return request.error();
        }
        if (auto status = renderer.set_volume(table_volume); !status) {
            return status.error();
        }
        ModeBench bench(renderer, *request, sweep.repeat);
        if (auto table = measure_optimisations(bench, sweep.modes, *table_volume, stdout); !table) {
            return table.error();
        }
        if (contains(sweep.modes, scene::Mode::phong)) {
            phong_cases.push_back({table_volume, std::move(request.value())});
        }
    }
    return phong_cases;
}

base::Result<std::unique_ptr<render::Renderer>> bench_renderer(const Arguments& a,
                                                               const OptimisationOptions& options) {
    return render::Renderer::create({.shader_dir = {},
                                     .debug_context = a.has("debug-gl"),
                                     .brick_voxels = options.brick_voxels,
                                     .gradients = options.gradients});
}

// The sweeps over slices and light-buffer resolutions, on the volume of --volume.
base::Status measure_sweeps(const Arguments& a, ModeBench& bench, const ModesSweep& sweep,
                            std::ofstream& csv) {
    const scene::RenderSettings& s = bench.base().settings;
    TimedResults results(csv.is_open() ? &csv : nullptr, s.width, s.height, sweep.repeat);
    ModesRun run{bench,        results,           sweep.modes,
                 sweep.slices, sweep.resolutions, scene::to_string(s.light_buffer.builder)};
    for (const auto measure :
         {measure_frames, measure_light_buffer_modes, measure_builders, measure_lookups}) {
        if (auto status = measure(run); !status) {
            return status;
        }
    }
    print_ratios(run);
    if (const auto csv_path = a.get("csv")) {
        std::printf("csv:      %s\n", csv_path->c_str());
    }
    return base::Ok{};
}

// Everything measured with the bench's renderer, which is gone when this returns; the volumes
// whose gradient sources are to be compared.
base::Result<std::vector<TableVolume>> measure_with_renderer(const Arguments& a,
                                                             const ModesSweep& sweep,
                                                             const OptimisationOptions& options) {
    const std::string path = a.get("volume").value_or(default_volume_path);
    auto loaded = volume::load_volume(path);
    if (!loaded) {
        return loaded.error();
    }
    auto volume = std::make_shared<const volume::Volume>(std::move(loaded.value()));
    auto base_request = frame_request_from(a, *volume);
    if (!base_request) {
        return base_request.error();
    }
    // Opened before anything is measured, so that a path it cannot write fails at once.
    std::ofstream csv;
    if (const auto csv_path = a.get("csv")) {
        csv.open(*csv_path);
        if (!csv) {
            return base::make_error("io_error", "cannot write '" + *csv_path + "'", "--csv");
        }
    }
    auto renderer = bench_renderer(a, options);
    if (!renderer) {
        return renderer.error();
    }
    ModeBench bench(**renderer, std::move(base_request.value()), sweep.repeat);
    print_modes_header((*renderer)->info(), *volume, bench, sweep.repeat);
    auto phong_cases = measure_optimisation_tables(a, **renderer, sweep, options, volume, path);
    if (!phong_cases || options.only) {
        return phong_cases;
    }
    if (auto status = (*renderer)->set_volume(volume); !status) {
        return status.error();
    }
    if (auto status = measure_sweeps(a, bench, sweep, csv); !status) {
        return status.error();
    }
    return phong_cases;
}

int run_bench_modes(const std::vector<std::string>& args) {
    std::vector<std::string> valued = frame_option_names();
    valued.insert(valued.end(), {"volume", "volumes", "slices-list", "light-res-list", "repeat",
                                 "modes", "csv", "gradients", "brick-voxels"});
    std::vector<std::string> flags = frame_flag_names();
    flags.insert(flags.end(), {"help", "debug-gl", "optimisations-only"});
    auto parsed = Arguments::parse(args, valued, flags);
    if (!parsed) {
        return usage_error(parsed.error());
    }
    if (parsed->has("help")) {
        print_modes_usage();
        return 0;
    }
    const Arguments& a = *parsed;
    if (auto status = refuse_swept_options(a); !status) {
        return usage_error(status.error());
    }
    auto sweep = modes_sweep(a);
    if (!sweep) {
        return fail(sweep.error());
    }
    auto options = optimisation_options(a, a.get("volume").value_or(default_volume_path));
    if (!options) {
        return usage_error(options.error());
    }
    auto phong_cases = measure_with_renderer(a, *sweep, *options);
    if (!phong_cases) {
        return fail(phong_cases.error());
    }
    for (const auto& [volume, request] : *phong_cases) {
        if (auto compared = compare_gradients(volume, request, sweep->repeat, stdout); !compared) {
            return fail(compared.error());
        }
    }
    return 0;
}

}  // namespace

// In cmd_bench_accuracy.cpp.
int run_bench_accuracy(const std::vector<std::string>& args);

// In cmd_bench_refine.cpp.
int run_bench_refine(const std::vector<std::string>& args);

int run_bench(const std::vector<std::string>& args) {
    if (args.empty()) {
        print_bench_usage();
        return 2;
    }
    if (args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
        print_bench_usage();
        return 0;
    }
    if (args[0] == "accuracy") {
        return run_bench_accuracy({args.begin() + 1, args.end()});
    }
    if (args[0] == "refine") {
        return run_bench_refine({args.begin() + 1, args.end()});
    }
    if (args[0] != "modes") {
        std::fprintf(stderr, "penumbra bench: unknown benchmark '%s'\n\n", args[0].c_str());
        print_bench_usage();
        return 2;
    }
    return run_bench_modes({args.begin() + 1, args.end()});
}

}  // namespace penumbra::app