// `penumbra bench refine`: how progressive stills approach the exact image. One view is rendered
// at 1/8 of the sample distance (the reference), once unjittered at the sample distance, and then
// jittered with its refinement steps averaged on the GPU; each frame's PSNR against the reference
// and time are printed. Optionally the unjittered and the last refined frame are written out.

#include "arguments.hpp"
#include "commands.hpp"
#include "render_options.hpp"

#include <penumbra/encode/compare.hpp>
#include <penumbra/encode/encode.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/volume/volume.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace penumbra::app {
namespace {

constexpr double reference_step_divisor = 8.0;

int fail(const base::Error& error) {
    return report_failure("bench refine", error);
}

void print_refine_usage() {
    std::printf(
            "usage: penumbra bench refine [options]\n"
            "\n"
            "PSNR against a reference at 1/8 of the sample distance: the unjittered frame, then\n"
            "the jittered still and each refinement step (the GPU's running mean).\n"
            "\n"
            "  --volume PATH    (default %s)\n"
            "  --steps K        refinement steps after the still (default 8, 1..%d)\n"
            "  --images PREFIX  write PREFIX_rings.png (unjittered) and PREFIX_refined.png\n"
            "%s",
            default_volume_path, scene::kMaxRefinementSteps, frame_options_help());
}

double psnr(const base::ImageRgba8& image, const base::ImageRgbaF& reference) {
    auto difference = encode::compare_images(base::to_rgba_f(image), reference);
    return difference ? difference->psnr : 0.0;
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
    const Arguments& a = *parsed;
    auto steps = a.integer("steps", 8);
    if (!steps || *steps < 1 || *steps > scene::kMaxRefinementSteps) {
        return fail(
                steps ? base::make_error("invalid_argument",
                                         "expects 1.." + std::to_string(scene::kMaxRefinementSteps),
                                         "--steps")
                      : steps.error());
    }
    auto loaded = volume::load_volume(a.get("volume").value_or(default_volume_path));
    if (!loaded) {
        return fail(loaded.error());
    }
    auto volume = std::make_shared<const volume::Volume>(std::move(loaded.value()));
    auto base_request = frame_request_from(a, *volume);
    if (!base_request) {
        return fail(base_request.error());
    }
    auto renderer = render::Renderer::create();
    if (!renderer) {
        return fail(renderer.error());
    }
    if (auto status = (*renderer)->set_volume(volume); !status) {
        return fail(status.error());
    }
    const auto render = [&](const scene::FrameRequest& request, double& ms) {
        const auto start = std::chrono::steady_clock::now();
        auto frame = (*renderer)->render(request);
        ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                     .count();
        return frame;
    };

    scene::FrameRequest unjittered = *base_request;
    unjittered.settings.jitter = false;
    scene::FrameRequest fine = unjittered;
    fine.settings.sample_distance /= reference_step_divisor;
    double ms = 0.0;
    auto reference = render(fine, ms);
    if (!reference) {
        return fail(reference.error());
    }
    const base::ImageRgbaF exact = base::to_rgba_f(reference->image);
    const scene::RenderSettings& s = unjittered.settings;
    std::printf(
            "penumbra bench refine: %s %dx%d, sample distance %g, reference at 1/%g of it "
            "(%.0f ms)\n",
            scene::to_string(s.mode), s.width, s.height, s.sample_distance, reference_step_divisor,
            ms);
    auto rings = render(unjittered, ms);
    if (!rings) {
        return fail(rings.error());
    }
    const double unjittered_psnr = psnr(rings->image, exact);
    std::printf("  unjittered        PSNR %6.2f dB  %8.1f ms\n", unjittered_psnr, ms);

    scene::FrameRequest request = unjittered;
    request.settings.jitter = true;
    request.refinement = {true, 0};
    base::ImageRgba8 last;
    double previous = 0.0;
    bool rising = true;
    for (int step = 0; step <= *steps; ++step) {
        if (step > 0) {
            request.refinement = {false, step};
        }
        auto frame = render(request, ms);
        if (!frame) {
            return fail(frame.error());
        }
        const double value = psnr(frame->image, exact);
        rising = rising && (step == 0 || value > previous);
        std::printf("  jittered step %-3d PSNR %6.2f dB  %8.1f ms  (%+.2f dB vs unjittered)\n",
                    step, value, ms, value - unjittered_psnr);
        previous = value;
        last = std::move(frame->image);
    }
    std::printf(
            "  PSNR rose with every step: %s; after %d steps %+.2f dB over the unjittered "
            "frame\n",
            rising ? "yes" : "no", *steps, previous - unjittered_psnr);
    if (const auto prefix = a.get("images")) {
        for (const auto& [suffix, image] :
             {std::pair<const char*, const base::ImageRgba8*>{"_rings.png", &rings->image},
              {"_refined.png", &last}}) {
            const std::filesystem::path path = *prefix + suffix;
            if (auto status = encode::write_image(path, *image); !status) {
                return fail(status.error());
            }
            std::printf("  wrote %s\n", path.c_str());
        }
    }
    return 0;
}

}  // namespace penumbra::app
