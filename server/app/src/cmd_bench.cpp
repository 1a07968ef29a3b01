#include "arguments.hpp"
#include "commands.hpp"
#include "render_options.hpp"

#include <penumbra/quality/modes_bench.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/volume/volume.hpp>

#include <cstdio>
#include <fstream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::app {
namespace {

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
            "                                 the renderer's default (automatic: central\n"
            "                                 differences, which the reference matches)\n"
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

// What `bench modes` sweeps, into `config`.
base::Status read_sweep(const Arguments& a, quality::ModesBenchConfig& config) {
    auto slice_counts = parse_counts(a.get("slices-list").value_or("64,128,256"), "slices-list");
    auto resolutions =
            parse_counts(a.get("light-res-list").value_or("128,256,512"), "light-res-list");
    auto modes = parse_modes(a.get("modes").value_or(scene::mode_names(",")), "modes");
    auto repeat = a.integer("repeat", config.repeat);
    if (!slice_counts || !resolutions || !modes || !repeat) {
        return !slice_counts  ? slice_counts.error()
               : !resolutions ? resolutions.error()
               : !modes       ? modes.error()
                              : repeat.error();
    }
    if (*repeat < 1 || *repeat > 1000) {
        return base::make_error("invalid_argument", "expects 1..1000", "--repeat");
    }
    config.slices = std::move(*slice_counts);
    config.resolutions = std::move(*resolutions);
    config.modes = std::move(*modes);
    config.repeat = *repeat;
    return base::Ok{};
}

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

// The optimisation table's options, into `config`.
base::Status read_optimisation_options(const Arguments& a, quality::ModesBenchConfig& config) {
    config.volumes = split_list(a.get("volumes").value_or(config.volume));
    if (config.volumes.empty()) {
        return base::make_error("invalid_argument", "expects FILE,...", "--volumes");
    }
    const auto gradients = parse_gradient_source(a.get("gradients").value_or("automatic"));
    if (!gradients) {
        return base::make_error("invalid_argument", "expects automatic, central or texture",
                                "--gradients");
    }
    config.gradients = *gradients;
    auto brick_voxels = a.integer("brick-voxels", 0);
    if (!brick_voxels) {
        return brick_voxels.error();
    }
    if (*brick_voxels < 0 || *brick_voxels > 256) {
        return base::make_error("invalid_argument",
                                "expects 1..256, or 0 for the renderer's default",
                                "--brick-voxels");
    }
    config.brick_voxels = *brick_voxels;
    config.only_table = a.has("optimisations-only");
    if (config.only_table && a.has("csv")) {
        return base::make_error("invalid_argument",
                                "the optimisation table writes no CSV; its rows are printed",
                                "--csv");
    }
    return base::Ok{};
}

// Opened before anything is measured, so that a path it cannot write fails at once.
base::Status open_csv(const Arguments& a, std::ofstream& csv, quality::ModesBenchConfig& config) {
    if (const auto csv_path = a.get("csv")) {
        csv.open(*csv_path);
        if (!csv) {
            return base::make_error("io_error", "cannot write '" + *csv_path + "'", "--csv");
        }
        config.csv = &csv;
        config.csv_path = *csv_path;
    }
    return base::Ok{};
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
    quality::ModesBenchConfig config;
    config.volume = a.get("volume").value_or(default_volume_path);
    config.debug_gl = a.has("debug-gl");
    config.frame_for = [&a](const volume::Volume& volume) { return frame_request_from(a, volume); };
    if (auto status = read_sweep(a, config); !status) {
        return fail(status.error());
    }
    if (auto status = read_optimisation_options(a, config); !status) {
        return usage_error(status.error());
    }
    std::ofstream csv;
    if (auto status = open_csv(a, csv, config); !status) {
        return fail(status.error());
    }
    if (auto status = quality::bench_modes(config, stdout); !status) {
        return fail(status.error());
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