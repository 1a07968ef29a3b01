// `penumbra bench truth`: the options of bench::bench_truth, which shows that the converged truth
// of `bench accuracy` has converged: the truth at each sample distance against the truth at the
// next finer one.

#include "commands.hpp"
#include "framed_volume.hpp"
#include "sweep_lists.hpp"
#include "truth_option.hpp"

#include <penumbra/bench/report.hpp>
#include <penumbra/bench/truth.hpp>
#include <penumbra/cli/frame_options.hpp>
#include <penumbra/cli/options.hpp>
#include <penumbra/quality/sweep.hpp>
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
    return report_failure("bench truth", error);
}

// The truth's own distance with twice and half of it.
std::string default_distances() {
    const double s = bench::kTruth.sample_distance;
    return bench::distance_label(2.0 * s) + "," + bench::distance_label(s) + "," +
           bench::distance_label(s / 2.0);
}

po::options_description truth_options(std::string& volume) {
    po::options_description options = option_group("options");
    options.add_options()("help", "this text")(
            "volume", po::value(&volume)->value_name("PATH")->default_value(volume), "the volume")(
            "sample-distances", with_default<Distances>("D,...", default_distances()),
            "the truth's sample distances, each compared with the next finer one")(
            "frames", with_default<Counts>("N,...", std::to_string(bench::kTruth.frames)),
            "frames averaged (a jittered still and its refinement steps), 2..257");
    add_truth_cache_option(options);
    options.add(frame_options({"sample-distance", "jitter"}));
    return options;
}

// Loads the volume, builds the frame and measures on a renderer of its own.
base::Status bench_truth(const po::variables_map& a, const std::string& path) {
    auto framed = framed_volume(a, path);
    if (!framed) {
        return framed.error();
    }
    const scene::RenderSettings& s = framed->frame.settings;
    std::printf("penumbra bench truth: %s %dx%d, tf %s, phong %s\n", framed->volume->name.c_str(),
                s.width, s.height, framed->frame.transfer_function.name.c_str(),
                s.phong ? "on" : "off");
    quality::AccuracyBench bench(*framed->renderer, 1);
    bench::TruthCache cache(truth_folder(a));
    return bench::bench_truth(bench, cache, *framed->volume, framed->frame,
                              a["sample-distances"].as<Distances>().values,
                              a["frames"].as<Counts>().values, stdout);
}

}  // namespace

int run_bench_truth(const std::vector<std::string>& args) {
    std::string volume = default_volume_path;
    const po::options_description options = truth_options(volume);
    auto parsed = parse_options(args, options);
    if (!parsed) {
        return report_usage_error("bench truth", parsed.error());
    }
    if (parsed->count("help") != 0) {
        print_help("bench truth [options]",
                   "Whether the converged truth of `bench accuracy` (" +
                           bench::describe(bench::kTruth) +
                           ")\nhas converged: the truth at each sample distance and frame count, "
                           "against the truth at the\nnext finer distance and at the next frame "
                           "count (PSNR, SSIM).",
                   options);
        return 0;
    }
    if (auto status = bench_truth(*parsed, volume); !status) {
        return fail(status.error());
    }
    return 0;
}

}  // namespace penumbra::app
