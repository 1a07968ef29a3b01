// `penumbra bench refine`: the options of bench::bench_refinement.

#include "commands.hpp"
#include "framed_volume.hpp"

#include <penumbra/bench/refine_bench.hpp>
#include <penumbra/cli/frame_options.hpp>
#include <penumbra/cli/options.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/volume/volume.hpp>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace penumbra::app {

using namespace cli;

namespace {

int fail(const base::Error& error) {
    return report_failure("bench refine", error);
}

po::options_description refine_options(std::string& volume, bench::RefineOptions& o) {
    po::options_description options = option_group("options");
    options.add_options()("help", "this text")(
            "volume", po::value(&volume)->value_name("PATH")->default_value(volume), "the volume")(
            "steps", whole_number(&o.steps, 1, scene::kMaxRefinementSteps),
            "refinement steps after the still")(
            "images", po::value<std::string>()->value_name("PREFIX"),
            "write PREFIX_rings.png (unjittered) and PREFIX_refined.png");
    options.add(frame_options());
    return options;
}

// Loads the volume, builds the frame and measures on a renderer of its own.
base::Status bench_refine(const po::variables_map& a, const std::string& path,
                          const bench::RefineOptions& options) {
    auto framed = framed_volume(a, path);
    if (!framed) {
        return framed.error();
    }
    auto result = bench::bench_refinement(*framed->renderer, framed->frame, options, stdout);
    if (!result) {
        return result.error();
    }
    return base::Ok{};
}

}  // namespace

int run_bench_refine(const std::vector<std::string>& args) {
    std::string volume = default_volume_path;
    bench::RefineOptions refine;
    const po::options_description options = refine_options(volume, refine);
    auto parsed = parse_options(args, options);
    if (!parsed) {
        return report_usage_error("bench refine", parsed.error());
    }
    if (parsed->count("help") != 0) {
        print_help("bench refine [options]",
                   "PSNR against a reference at 1/" + shown(bench::refine_reference_divisor) +
                           " of the sample distance: the unjittered frame, then the jittered "
                           "still\nand each refinement step (the GPU's running mean).",
                   options);
        return 0;
    }
    if (parsed->count("images") != 0) {
        refine.images = (*parsed)["images"].as<std::string>();
    }
    if (auto status = bench_refine(*parsed, volume, refine); !status) {
        return fail(status.error());
    }
    return 0;
}

}  // namespace penumbra::app
