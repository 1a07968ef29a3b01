// `penumbra bench refine`: the options of quality::bench_refinement.

#include "arguments.hpp"
#include "commands.hpp"
#include "render_options.hpp"

#include <penumbra/quality/refine_bench.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/volume/volume.hpp>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace penumbra::app {
namespace {

int fail(const base::Error& error) {
    return report_failure("bench refine", error);
}

void print_refine_usage() {
    std::printf(
            "usage: penumbra bench refine [options]\n"
            "\n"
            "PSNR against a reference at 1/%g of the sample distance: the unjittered frame, then\n"
            "the jittered still and each refinement step (the GPU's running mean).\n"
            "\n"
            "  --volume PATH    (default %s)\n"
            "  --steps K        refinement steps after the still (default 8, 1..%d)\n"
            "  --images PREFIX  write PREFIX_rings.png (unjittered) and PREFIX_refined.png\n"
            "%s",
            quality::refine_reference_divisor, default_volume_path, scene::kMaxRefinementSteps,
            frame_options_help());
}

base::Result<quality::RefineOptions> refine_options(const Arguments& a) {
    quality::RefineOptions options;
    auto steps = a.integer("steps", options.steps);
    if (!steps) {
        return steps.error();
    }
    if (*steps < 1 || *steps > scene::kMaxRefinementSteps) {
        return base::make_error("invalid_argument",
                                "expects 1.." + std::to_string(scene::kMaxRefinementSteps),
                                "--steps");
    }
    options.steps = *steps;
    options.images = a.get("images");
    return options;
}

// Loads the volume, builds the frame and measures on a renderer of its own.
base::Status bench_refine(const Arguments& a, const quality::RefineOptions& options) {
    auto loaded = volume::load_volume(a.get("volume").value_or(default_volume_path));
    if (!loaded) {
        return loaded.error();
    }
    auto volume = std::make_shared<const volume::Volume>(std::move(loaded.value()));
    auto frame = frame_request_from(a, *volume);
    if (!frame) {
        return frame.error();
    }
    auto renderer = render::Renderer::create();
    if (!renderer) {
        return renderer.error();
    }
    if (auto status = (*renderer)->set_volume(volume); !status) {
        return status;
    }
    auto result = quality::bench_refinement(**renderer, *frame, options, stdout);
    if (!result) {
        return result.error();
    }
    return base::Ok{};
}

}  // namespace

int run_bench_refine(const std::vector<std::string>& args) {
    std::vector<std::string> valued = frame_option_names();
    valued.insert(valued.end(), {"volume", "steps", "images"});
    std::vector<std::string> flags = frame_flag_names();
    flags.push_back("help");
    auto parsed = Arguments::parse(args, valued, flags);
    if (!parsed) {
        return report_usage_error("bench refine", parsed.error());
    }
    if (parsed->has("help")) {
        print_refine_usage();
        return 0;
    }
    auto options = refine_options(*parsed);
    if (!options) {
        return fail(options.error());
    }
    if (auto status = bench_refine(*parsed, *options); !status) {
        return fail(status.error());
    }
    return 0;
}

}  // namespace penumbra::app
