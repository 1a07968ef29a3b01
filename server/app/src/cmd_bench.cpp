#include "commands.hpp"
#include "sweep_lists.hpp"

#include <penumbra/base/text.hpp>
#include <penumbra/bench/modes_bench.hpp>
#include <penumbra/cli/frame_options.hpp>
#include <penumbra/cli/options.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/volume/volume.hpp>

#include <cstdio>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::app {

using namespace cli;

namespace {

int fail(const base::Error& error) {
    return report_failure("bench modes", error);
}

int usage_error(const base::Error& error) {
    return report_usage_error("bench modes", error);
}

const SweptOptions swept = {{"mode", "--modes LIST"},
                            {"slices", "--slices-list LIST"},
                            {"light-res", "--light-res-list LIST"}};

po::options_description modes_options(bench::ModesBenchConfig& config) {
    po::options_description options = option_group("options");
    options.add_options()("help", "this text")(
            "volume", po::value(&config.volume)->value_name("FILE")->default_value(config.volume),
            "the volume the sweeps run on")(
            "modes", po::value<Modes>()->value_name("LIST"),
            "modes to time, comma-separated (default: every mode); the builder comparison runs "
            "when a sbrc mode is listed")(
            "slices-list", with_default<Counts>("N,...", "64,128,256"), "light slices to sweep")(
            "light-res-list", with_default<Counts>("R,...", "128,256,512"),
            "light-buffer resolutions to sweep")("repeat", whole_number(&config.repeat, 1, 1000),
                                                 "timed frames per point after 1 warm-up")(
            "volumes", po::value<std::string>()->value_name("FILE,..."),
            "volumes for the optimisation table (default: the --volume)")(
            "gradients",
            po::value<std::string>()
                    ->value_name("automatic|central|texture")
                    ->default_value("automatic"),
            "where shaded samples get gradients: central differences, the precomputed texture, or "
            "the renderer's default (automatic: central differences, which the reference matches)")(
            "brick-voxels", po::value(&config.brick_voxels)->value_name("N")->default_value(0),
            "voxels per side of the bricks empty-space skipping leaps over (0: the renderer's)")(
            "optimisations-only",
            "only the optimisation table: each mode's frame time with and without empty-space "
            "skipping, the PSNR between the two images, the light-buffer build with and without, "
            "and phong with central differences against the gradient texture")(
            "labels", po::value(&config.labels)->value_name("FILE"),
            "also a table of each mode with this label map drawn inside the --volume (the AAL "
            "atlas over ch2: /usr/share/mricron/templates/aal.nii.gz)")(
            "csv", po::value<std::string>()->value_name("FILE"),
            "also write one row per point of the sweeps")("debug-gl", "GL debug output to the log");
    options.add(frame_options(names_of(swept)));
    return options;
}

// The optimisation table's options, into `config`.
base::Status read_optimisation_options(const po::variables_map& a,
                                       bench::ModesBenchConfig& config) {
    config.volumes = base::split_list(a.count("volumes") != 0 ? a["volumes"].as<std::string>()
                                                              : config.volume);
    if (config.volumes.empty()) {
        return base::make_error(base::ErrorCode::invalid_argument, "expects FILE,...", "--volumes");
    }
    const auto gradients = render::parse_gradient_source(a["gradients"].as<std::string>());
    if (!gradients) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "expects automatic, central or texture", "--gradients");
    }
    config.gradients = *gradients;
    if (config.brick_voxels < 0 || config.brick_voxels > 256) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "expects 1..256, or 0 for the renderer's default",
                                "--brick-voxels");
    }
    config.only_table = a.count("optimisations-only") != 0;
    if (config.only_table && a.count("csv") != 0) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "the optimisation table writes no CSV; its rows are printed",
                                "--csv");
    }
    return base::Ok{};
}

// Opened before anything is measured, so that a path it cannot write fails at once.
base::Status open_csv(const po::variables_map& a, std::ofstream& csv,
                      bench::ModesBenchConfig& config) {
    if (a.count("csv") != 0) {
        config.csv_path = a["csv"].as<std::string>();
        csv.open(config.csv_path);
        if (!csv) {
            return base::make_error(base::ErrorCode::io_error,
                                    "cannot write '" + config.csv_path + "'", "--csv");
        }
        config.csv = &csv;
    }
    return base::Ok{};
}

int run_bench_modes(const std::vector<std::string>& args) {
    bench::ModesBenchConfig config;
    config.volume = default_volume_path;
    const po::options_description options = modes_options(config);
    auto parsed = parse_options(args, options);
    if (!parsed) {
        return usage_error(explain_swept(parsed.error(), swept, "bench modes"));
    }
    const po::variables_map& a = *parsed;
    if (a.count("help") != 0) {
        print_help("bench modes [options]",
                   "Times each mode side by side in one run and prints the ratios that matter: "
                   "half_angle vs sbrc\nat equal slices, sbrc's growth with slices, per_slice vs "
                   "multi_slice builder, the local light\nlookup vs the paper's (--light-lookup "
                   "interpolate --slab-samples 1). Absolute times mean\nsomething only on a GPU; "
                   "on a software rasteriser read the ratios.",
                   options);
        return 0;
    }
    config.debug_gl = a.count("debug-gl") != 0;
    config.frame_for = [&a](const volume::Volume& volume) { return frame_request_from(a, volume); };
    config.slices = a["slices-list"].as<Counts>().values;
    config.resolutions = a["light-res-list"].as<Counts>().values;
    config.modes = a.count("modes") != 0 ? a["modes"].as<Modes>().values
                                         : cli::parsed<Modes>(scene::mode_names(",")).values;
    if (auto status = read_optimisation_options(a, config); !status) {
        return usage_error(status.error());
    }
    std::ofstream csv;
    if (auto status = open_csv(a, csv, config); !status) {
        return fail(status.error());
    }
    if (auto status = bench::bench_modes(config, stdout); !status) {
        return fail(status.error());
    }
    return 0;
}

}  // namespace

int run_bench(const std::vector<std::string>& args) {
    return run_subcommand(
            "penumbra bench", "benchmark",
            {{"modes",
              "frame time of every rendering mode over slices x light-buffer resolution,\n\t"
              "light-buffer reuse vs rebuild, and the two light-buffer builders",
              run_bench_modes},
             {"accuracy",
              "error vs the converged truth and vs the reference of the same sample\n\tdistance "
              "(RMSE, PSNR, SSIM) against frame time over modes x slices x\n\tlight-buffer "
              "resolution x sample distance; quality presets per frame-time\n\tbudget; CSV, "
              "JSON and a plot",
              run_bench_accuracy},
             {"encode",
              "milliseconds and bytes per frame, JPEG and PNG: TurboJPEG and libpng\n\tagainst "
              "OpenImageIO's writers, on rendered frames",
              run_bench_encode},
             {"refine",
              "progressive stills: PSNR of each refinement step against a reference at\n\t1/8 "
              "of the sample distance, next to the unjittered frame",
              run_bench_refine},
             {"stills",
              "every mode's interactive frame, first still and converged still against\n\tthe "
              "converged truth on the four accuracy cases (PSNR, SSIM, time), and\n\tthe "
              "default mode's targets",
              run_bench_stills},
             {"truth",
              "the converged truth of `bench accuracy` at each sample distance against\n\tthe "
              "next finer one: whether halving the distance still changes the image",
              run_bench_truth}},
            args);
}

}  // namespace penumbra::app
