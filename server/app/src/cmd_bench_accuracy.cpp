// `penumbra bench accuracy`: what each method's accuracy costs in time (DESIGN.md §1 "Accuracy and
// its cost in time"). Every method is rendered from the same camera as the converged truth (the
// `reference` mode, shadow rays marched to the light at every sample, at a fine jittered step
// averaged over frames: bench/truth.hpp) and as a `reference` frame of the same sample distance;
// the errors against both are set beside the frame time. The measured table doubles as the source
// of quality presets: for a frame-time budget, the most accurate setting that fits.

#include "commands.hpp"
#include "sweep_lists.hpp"
#include "truth_option.hpp"

#include <penumbra/base/data_dir.hpp>
#include <penumbra/base/text.hpp>
#include <penumbra/bench/accuracy_bench.hpp>
#include <penumbra/bench/sweep_spec.hpp>
#include <penumbra/bench/truth.hpp>
#include <penumbra/cli/frame_options.hpp>
#include <penumbra/cli/options.hpp>
#include <penumbra/cli/transfer_function_file.hpp>
#include <penumbra/imageio/imageio.hpp>
#include <penumbra/quality/sweep.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/volume/volume.hpp>

#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace penumbra::app {

using namespace cli;

namespace {

using namespace quality;
using namespace bench;

std::string cases_help() {
    std::string help;
    for (const AccuracyCase& c : accuracy_cases()) {
        char line[256];
        std::snprintf(line, sizeof line, "\n  %-15s \ttf %s: %s", c.name, c.transfer_function,
                      c.what);
        help += line;
    }
    return help;
}

int fail(const base::Error& error) {
    return report_failure("bench accuracy", error);
}

int usage_error(const base::Error& error) {
    return report_usage_error("bench accuracy", error);
}

// What the benchmark sweeps or fixes itself; accepting one would silently ignore it.
const SweptOptions swept = {{"mode", "--modes LIST"},
                            {"slices", "--slices-list LIST"},
                            {"light-res", "--light-res-list LIST"},
                            {"light", "--lights LIST"},
                            {"light-position", "--lights LIST (directional lights only)"},
                            {"sample-distance", "--sample-distances LIST"},
                            {"no-empty-space-skipping", "--skipping on,off"}};

// "(default GPU [software rasteriser])".
std::string defaults_of(const std::string& gpu, const std::string& software) {
    return " (default " + gpu + (gpu == software ? "" : " [" + software + "]") + ")";
}

po::options_description sweep_options() {
    const SweepDefaults& gpu = sweep_defaults(true);
    const SweepDefaults& cpu = sweep_defaults(false);
    const auto list = [](const char* name) { return po::value<std::string>()->value_name(name); };
    po::options_description options = option_group(
            "sweep (defaults for a GPU, on a software rasteriser such as llvmpipe lighter ones in "
            "[])");
    const std::string lights =
            "directional lights in degrees, quote the ';'" + defaults_of(gpu.lights, cpu.lights);
    const std::string distances =
            "numbers or 1/N" + defaults_of(gpu.sample_distances, cpu.sample_distances);
    const std::string slices = "light slices" + defaults_of(gpu.slices, cpu.slices);
    const std::string resolutions =
            "light-buffer resolutions" + defaults_of(gpu.resolutions, cpu.resolutions);
    const std::string cases = "a transfer function and the volumes it suits:" + cases_help();
    const std::string repeat = "timed frames per point after 1 warm-up" +
                               defaults_of(std::to_string(gpu.repeat), std::to_string(cpu.repeat));
    options.add_options()("volumes", list("FILE,..."),
                          "(default ch2, ch2better, inia19-t1-brain from mricron-data [ch2], and "
                          "the head CT that scripts/demo-data.sh converts, where it did)")(
            "lights", po::value<Lights>()->value_name("AZ,EL;AZ,EL..."), lights.c_str())(
            "modes", po::value<Modes>()->value_name("LIST"),
            "(default: every mode; the reference is always rendered)")(
            "slices-list", po::value<Counts>()->value_name("N,..."), slices.c_str())(
            "light-res-list", po::value<Counts>()->value_name("R,..."), resolutions.c_str())(
            "sample-distances", po::value<Distances>()->value_name("D,..."), distances.c_str())(
            "skipping", with_default<Switches>("on,off", "on"),
            "empty-space skipping on and/or off, every setting and the reference")(
            "jitter", with_default<Switches>("off,on", "off"),
            "ray-cast modes unjittered and/or jittered (the reference never jitters)")(
            "refinement", with_default<Steps>("K,...", "0"),
            "jittered settings also refined by K steps, each a point (needs --jitter with on)")(
            "case", list("NAME"), cases.c_str())("repeat", po::value<int>()->value_name("N"),
                                                 repeat.c_str());
    return options;
}

po::options_description output_options() {
    po::options_description options = option_group("output");
    options.add_options()("help", "this text")("no-phong",
                                               "shadow modes and reference without Blinn-Phong")(
            "csv", po::value<std::string>()->value_name("FILE"), "the measured table as CSV")(
            "images", po::value<std::string>()->value_name("DIR"),
            "every point's image as a PNG in DIR (made if missing), named after the point")(
            "json", po::value<std::string>()->value_name("FILE"), "... as JSON")(
            "plot", po::value<std::string>()->value_name("FILE.png"),
            "PSNR over frame time, one curve per method, Pareto front marked; also FILE.svg and "
            "the gnuplot script FILE.gp (needs gnuplot-nox)")(
            "budget-ms", po::value<Numbers>()->value_name("MS,..."),
            "frame-time budgets for the quality presets (default: six from the fastest setting "
            "to the reference)")("from", po::value<std::string>()->value_name("FILE.json"),
                                 "measure nothing: presets, CSV, JSON and plot from a table "
                                 "written by --json")("debug-gl", "GL debug output to the log");
    add_truth_cache_option(options);
    return options;
}

constexpr const char* about =
        "Accuracy against the converged truth versus frame time. For every volume and light the "
        "truth\n(the `reference` mode, shadow rays, at a fine jittered step averaged over "
        "frames; kept on disk,\n--truth-cache) and the reference at every sample distance are "
        "rendered from the same camera;\nevery mode x slices x light-buffer resolution x "
        "sample distance, and each reference, is compared\nwith the truth and with the "
        "reference of its own sample distance (RMSE and PSNR via OpenImageIO,\nSSIM on Rec. "
        "601 luma) and timed: the median "
        "frame time over --repeat frames with the light\nbuffer cached (what a user orbiting "
        "the volume pays), and the median light-buffer build forced\nby nudging the light "
        "(what a light or TF edit pays). Times are GPU timer queries where they\nwork, else "
        "wall clock. Phong shading is on in every mode that has it as an option, so the\n"
        "methods differ only in how they shadow; dvr is unlit. The frame options are those of "
        "`render`,\nless what the sweep varies.";

// The presets' budgets and the files the options ask for.
AccuracyReport report_from(const po::variables_map& a) {
    AccuracyReport report;
    if (a.count("budget-ms") != 0) {
        report.budgets_ms = a["budget-ms"].as<Numbers>().values;
    }
    for (auto [name, file] : {std::pair{"csv", &report.csv}, std::pair{"json", &report.json},
                              std::pair{"plot", &report.plot}}) {
        if (a.count(name) != 0) {
            *file = a[name].as<std::string>();
        }
    }
    return report;
}

// --case, where one is named.
base::Result<const AccuracyCase*> case_from(const po::variables_map& a) {
    if (a.count("case") == 0) {
        return nullptr;
    }
    auto named = accuracy_case_named(a["case"].as<std::string>());
    if (named && a.count("tf") != 0) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "--case sets the transfer function; give one or the other", "--tf");
    }
    return named;
}

// The values of list option `name`, where it was given.
template <class List>
void take(const po::variables_map& a, const char* name,
          std::optional<decltype(List::values)>& values) {
    if (a.count(name) != 0) {
        values = a[name].as<List>().values;
    }
}

// The sweep the options ask for.
SweepSpec spec_from(const po::variables_map& a, const AccuracyCase* accuracy_case) {
    SweepSpec spec;
    if (a.count("volumes") != 0) {
        spec.volumes = base::split_list(a["volumes"].as<std::string>());
    }
    take<Lights>(a, "lights", spec.lights);
    take<Modes>(a, "modes", spec.modes);
    take<Counts>(a, "slices-list", spec.slices);
    take<Counts>(a, "light-res-list", spec.resolutions);
    take<Distances>(a, "sample-distances", spec.distances);
    if (a.count("repeat") != 0) {
        spec.repeat = a["repeat"].as<int>();
    }
    spec.skipping = a["skipping"].as<Switches>().values;
    spec.jitter = a["jitter"].as<Switches>().values;
    spec.refinement_steps = a["refinement"].as<Steps>().values;
    spec.accuracy_case = accuracy_case;
    spec.head_ct = base::demo_ct_path();
    return spec;
}

// The frame every point of one volume shares: the frame options over the defaults.
base::Result<scene::FrameRequest> base_request(const po::variables_map& a,
                                               const volume::Volume& volume,
                                               const SweepDefaults& defaults,
                                               const AccuracyCase* accuracy_case, bool phong) {
    auto request = frame_request_from(a, volume);
    if (!request) {
        return request.error();
    }
    if (a["size"].defaulted()) {
        request->settings.width = defaults.side;
        request->settings.height = defaults.side;
    }
    if (request->settings.width < min_image_side || request->settings.height < min_image_side) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "SSIM needs images of at least " + std::to_string(min_image_side) +
                                        "x" + std::to_string(min_image_side),
                                "--size");
    }
    request->settings.phong = phong;
    if (accuracy_case != nullptr) {
        auto tf = load_transfer_function(accuracy_case->transfer_function, volume.range);
        if (!tf) {
            return tf.error();
        }
        request->transfer_function = std::move(*tf);
    }
    return request;
}

// Measures the sweep the options ask for and reports its table.
int measure(const po::variables_map& a, const AccuracyReport& report) {
    if (!imageio::available() && (report.json || report.plot)) {
        // Refused before measuring: report_accuracy would refuse them after the whole sweep.
        return usage_error(base::make_error(base::ErrorCode::image_io_unavailable,
                                            "this penumbra was built without OpenImageIO: it "
                                            "times frames and writes them (--csv, --images) but "
                                            "cannot measure the errors --json and --plot rank by",
                                            report.json ? "--json" : "--plot"));
    }
    auto renderer =
            render::Renderer::create({.shader_dir = {}, .debug_context = a.count("debug-gl") != 0});
    if (!renderer) {
        return fail(renderer.error());
    }
    const render::RendererInfo& info = (*renderer)->info();
    const SweepDefaults& defaults = sweep_defaults(info.gpu_timer_queries);
    auto accuracy_case = case_from(a);
    if (!accuracy_case) {
        return usage_error(accuracy_case.error());
    }
    auto sweep = make_sweep(spec_from(a, *accuracy_case), defaults);
    if (!sweep) {
        return usage_error(sweep.error());
    }
    if (a.count("images") != 0) {
        sweep->images = a["images"].as<std::string>();
        std::error_code failed;
        std::filesystem::create_directories(*sweep->images, failed);
        if (failed) {
            return fail(base::make_error(base::ErrorCode::write_failed, failed.message(),
                                         sweep->images->string()));
        }
    }
    Table table = make_table(info, sweep->repeat, a.count("no-phong") == 0);
    const FrameFor frame_for = [&](const volume::Volume& volume) {
        return base_request(a, volume, defaults, *accuracy_case, table.phong);
    };
    TruthCache truths(truth_folder(a));
    if (auto status = bench_accuracy(**renderer, *sweep, frame_for, truths, table, stdout);
        !status) {
        return status.error().where == "--size" ? usage_error(status.error())
                                                : fail(status.error());
    }
    if (auto status = report_accuracy(table, report, stdout); !status) {
        return fail(status.error());
    }
    return 0;
}

}  // namespace

int run_bench_accuracy(const std::vector<std::string>& args) {
    po::options_description options = sweep_options();
    std::vector<std::string> not_framed = names_of(swept);
    not_framed.push_back("jitter");  // a list here: --jitter off,on
    options.add(output_options()).add(frame_options(not_framed));
    auto parsed = parse_options(args, options);
    if (!parsed) {
        return usage_error(explain_swept(parsed.error(), swept, "bench accuracy"));
    }
    const po::variables_map& a = *parsed;
    if (a.count("help") != 0) {
        print_help("bench accuracy [options]", about, options);
        return 0;
    }
    const AccuracyReport report = report_from(a);
    if (a.count("from") != 0) {
        auto status = report_accuracy_file(a["from"].as<std::string>(), report, stdout);
        return status ? 0 : fail(status.error());
    }
    return measure(a, report);
}

}  // namespace penumbra::app
