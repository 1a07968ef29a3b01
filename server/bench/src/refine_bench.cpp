#include "penumbra/bench/refine_bench.hpp"

#include <penumbra/encode/encode.hpp>
#include <penumbra/imageio/compare.hpp>

#include <chrono>
#include <filesystem>
#include <limits>
#include <utility>

namespace penumbra::bench {
namespace {

// NaN, printed "nan", where it cannot be measured (a build without image comparison).
double psnr(const base::ImageRgba8& image, const base::ImageRgbaF& reference) {
    auto difference = imageio::compare_images(base::to_rgba_f(image), reference);
    return difference ? difference->psnr : std::numeric_limits<double>::quiet_NaN();
}

// Renders `request`, its wall time in `ms`.
base::Result<render::Frame> timed_render(render::FrameRenderer& renderer,
                                         const scene::FrameRequest& request, double& ms) {
    const auto start = std::chrono::steady_clock::now();
    auto frame = renderer.render(request);
    ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                 .count();
    return frame;
}

// The jittered still and its refinement steps, each printed as it comes; `last` is the image of
// the last step.
base::Status measure_steps(render::FrameRenderer& renderer, scene::FrameRequest request,
                           const base::ImageRgbaF& exact, const RefineOptions& options,
                           RefineResult& result, base::ImageRgba8& last, std::FILE* out) {
    request.settings.jitter = true;
    request.refinement = {true, 0};
    for (int step = 0; step <= options.steps; ++step) {
        if (step > 0) {
            request.refinement = {false, step};
        }
        RefineStep measured;
        auto frame = timed_render(renderer, request, measured.ms);
        if (!frame) {
            return frame.error();
        }
        measured.psnr = psnr(frame->image, exact);
        result.rising = result.rising && (step == 0 || measured.psnr > result.steps.back().psnr);
        std::fprintf(out,
                     "  jittered step %-3d PSNR %6.2f dB  %8.1f ms  (%+.2f dB vs unjittered)\n",
                     step, measured.psnr, measured.ms, measured.psnr - result.unjittered.psnr);
        result.steps.push_back(measured);
        last = std::move(frame->image);
    }
    return base::Ok{};
}

base::Status write_images(const std::string& prefix, const base::ImageRgba8& rings,
                          const base::ImageRgba8& refined, std::FILE* out) {
    for (const auto& [suffix, image] :
         {std::pair<const char*, const base::ImageRgba8*>{"_rings.png", &rings},
          {"_refined.png", &refined}}) {
        const std::filesystem::path path = prefix + suffix;
        if (auto status = encode::write_image(path, *image); !status) {
            return status;
        }
        std::fprintf(out, "  wrote %s\n", path.c_str());
    }
    return base::Ok{};
}

}  // namespace

base::Result<RefineResult> bench_refinement(render::FrameRenderer& renderer,
                                            const scene::FrameRequest& frame,
                                            const RefineOptions& options, std::FILE* out) {
    scene::FrameRequest unjittered = frame;
    unjittered.settings.jitter = false;
    scene::FrameRequest fine = unjittered;
    fine.settings.sample_distance /= refine_reference_divisor;
    double ms = 0.0;
    auto reference = timed_render(renderer, fine, ms);
    if (!reference) {
        return reference.error();
    }
    const base::ImageRgbaF exact = base::to_rgba_f(reference->image);
    const scene::RenderSettings& s = unjittered.settings;
    std::fprintf(out,
                 "penumbra bench refine: %s %dx%d, sample distance %g, reference at 1/%g of it "
                 "(%.0f ms)\n",
                 scene::to_string(s.mode), s.width, s.height, s.sample_distance,
                 refine_reference_divisor, ms);
    RefineResult result;
    auto rings = timed_render(renderer, unjittered, result.unjittered.ms);
    if (!rings) {
        return rings.error();
    }
    result.unjittered.psnr = psnr(rings->image, exact);
    std::fprintf(out, "  unjittered        PSNR %6.2f dB  %8.1f ms\n", result.unjittered.psnr,
                 result.unjittered.ms);
    base::ImageRgba8 last;
    if (auto status = measure_steps(renderer, unjittered, exact, options, result, last, out);
        !status) {
        return status.error();
    }
    std::fprintf(out,
                 "  PSNR rose with every step: %s; after %d steps %+.2f dB over the unjittered "
                 "frame\n",
                 result.rising ? "yes" : "no", options.steps,
                 result.steps.back().psnr - result.unjittered.psnr);
    if (options.images) {
        if (auto status = write_images(*options.images, rings->image, last, out); !status) {
            return status.error();
        }
    }
    return result;
}

}  // namespace penumbra::bench
