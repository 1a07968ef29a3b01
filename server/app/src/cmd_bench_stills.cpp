// `penumbra bench stills`: the options of bench::bench_stills, the table of the frames a user sees
// of every mode against the converged truth.

#include "commands.hpp"
#include "truth_option.hpp"

#include <penumbra/base/data_dir.hpp>
#include <penumbra/base/text.hpp>
#include <penumbra/bench/stills_bench.hpp>
#include <penumbra/bench/sweep_spec.hpp>
#include <penumbra/cli/frame_options.hpp>
#include <penumbra/cli/options.hpp>
#include <penumbra/cli/transfer_function_file.hpp>
#include <penumbra/render/renderer.hpp>

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::app {

using namespace cli;

namespace {

int fail(const base::Error& error) {
    return report_failure("bench stills", error);
}

std::string every_case() {
    std::string names;
    for (const bench::AccuracyCase& c : bench::accuracy_cases()) {
        names += (names.empty() ? "" : ",") + std::string(c.name);
    }
    return names;
}

po::options_description stills_options(bench::StillsConfig& config) {
    const scene::Setting& steps = scene::setting::refinement_steps;
    const scene::Setting& threshold = scene::setting::refinement_threshold;
    po::options_description options = option_group("options");
    options.add_options()("help", "this text")(
            "cases", po::value<std::string>()->value_name("LIST")->default_value(every_case()),
            "the accuracy cases (bench accuracy --help), each on its first volume: ch2 for "
            "mri_skin, the head CT that scripts/demo-data.sh converts for ct_*")(
            "volume", po::value<std::string>()->value_name("FILE"),
            "measure the cases on this volume instead")(
            "modes", po::value<Modes>()->value_name("LIST"), "the modes (default: every mode)")(
            "refinement-steps", whole_number(&config.max_steps, 1, static_cast<int>(steps.max)),
            std::string(steps.summary).c_str())(
            "refinement-threshold", number_within(&config.threshold, threshold.min, threshold.max),
            std::string(threshold.summary).c_str())(
            "repeat", whole_number(&config.repeat, 1, 1000),
            "timed frames of each still and interactive frame after 1 warm-up")(
            "images", po::value<std::string>()->value_name("DIR"),
            "write every frame and each case's truth there (CASE_MODE_FRAME.png, CASE_truth.png)")(
            "csv", po::value<std::string>()->value_name("FILE"), "also write the rows as CSV");
    add_truth_cache_option(options);
    options.add(frame_options({"mode", "tf", "jitter", "no-jitter"}, FramePurpose::still));
    return options;
}

// The cases --cases names, each on --volume or its first volume.
base::Result<std::vector<bench::StillsCase>> cases_from(const po::variables_map& a) {
    std::vector<bench::StillsCase> cases;
    for (const std::string& name : base::split_list(a["cases"].as<std::string>())) {
        auto named = bench::accuracy_case_named(name);
        if (!named) {
            return base::make_error(named.error().code, named.error().message, "--cases");
        }
        bench::SweepSpec spec;
        spec.accuracy_case = *named;
        spec.head_ct = base::demo_ct_path();
        if (a.count("volume") != 0) {
            spec.volumes = std::vector<std::string>{a["volume"].as<std::string>()};
        }
        auto volumes = bench::sweep_volumes(spec, bench::sweep_defaults(false));
        if (!volumes) {
            return base::make_error(volumes.error().code, volumes.error().message, "--cases");
        }
        cases.push_back({name, volumes->front()});
    }
    return cases;
}

int measure(const po::variables_map& a, bench::StillsConfig& config) {
    auto cases = cases_from(a);
    if (!cases) {
        return report_usage_error("bench stills", cases.error());
    }
    config.cases = std::move(*cases);
    config.modes = a.count("modes") != 0 ? a["modes"].as<Modes>().values
                                         : parsed<Modes>(scene::mode_names(",")).values;
    if (a.count("images") != 0) {
        config.images = a["images"].as<std::string>();
    }
    config.frame_for = [&a](const volume::Volume& volume,
                            const bench::StillsCase& c) -> base::Result<scene::FrameRequest> {
        auto request = frame_request_from(a, volume, FramePurpose::still);
        if (!request) {
            return request.error();
        }
        auto tf = load_transfer_function(bench::find_accuracy_case(c.name)->transfer_function,
                                         volume.range);
        if (!tf) {
            return tf.error();
        }
        request->transfer_function = std::move(*tf);
        return request;
    };
    auto renderer = render::Renderer::create();
    if (!renderer) {
        return fail(renderer.error());
    }
    bench::TruthCache truths(truth_folder(a));
    auto rows = bench::bench_stills(**renderer, config, truths, stdout);
    if (!rows) {
        return fail(rows.error());
    }
    if (a.count("csv") != 0) {
        if (auto status = bench::write_stills_csv(*rows, a["csv"].as<std::string>()); !status) {
            return fail(status.error());
        }
    }
    return 0;
}

}  // namespace

int run_bench_stills(const std::vector<std::string>& args) {
    bench::StillsConfig config;
    const po::options_description options = stills_options(config);
    auto parsed = parse_options(args, options);
    if (!parsed) {
        return report_usage_error("bench stills", parsed.error());
    }
    if (parsed->count("help") != 0) {
        print_help("bench stills [options]",
                   "What a user sees of every mode, against the converged truth (" +
                           bench::describe(bench::kTruth) +
                           "), from the view\n`penumbra render` gives by default: the still "
                           "unjittered (as it was before stills converged),\nthe interactive "
                           "frame (half the size and light buffer, twice the step, stretched back "
                           "as the\nbrowser shows it), the first jittered still and the still "
                           "refined until it stops changing, and the unjittered still given the "
                           "converged one's\ntime as before (its step halved while it fits). "
                           "PSNR, SSIM and time (the converged "
                           "still's: the still's and all its steps'), the truth at the\n"
                           "interactive size stretched back (what no interactive frame can beat), "
                           "then the default mode's\ntargets met or missed.",
                   options);
        return 0;
    }
    return measure(*parsed, config);
}

}  // namespace penumbra::app
