#pragma once

// `penumbra bench refine`: how progressive stills approach the exact image. One view is rendered
// at 1/8 of the sample distance (the reference), once unjittered at the sample distance, and then
// jittered with its refinement steps averaged on the GPU; each frame's PSNR against the reference
// and time are printed as they are measured.

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::bench {

// The reference's sample distance is the frame's divided by this.
inline constexpr double refine_reference_divisor = 8.0;

struct RefineOptions {
    int steps = 8;  // refinement steps after the jittered still, 1..scene::kMaxRefinementSteps
    // Where set, PREFIX_rings.png (the unjittered frame) and PREFIX_refined.png (the last step)
    // are written.
    std::optional<std::string> images;
};

struct RefineStep {
    double psnr = 0.0;  // against the reference, dB
    double ms = 0.0;    // the frame's wall time
};

struct RefineResult {
    RefineStep unjittered;
    std::vector<RefineStep> steps;  // the jittered still (step 0), then each refinement
    bool rising = true;             // PSNR rose with every step
};

// On `renderer`, whose volume is set, from `frame` (its jitter and refinement are replaced).
base::Result<RefineResult> bench_refinement(render::FrameRenderer& renderer,
                                            const scene::FrameRequest& frame,
                                            const RefineOptions& options, std::FILE* out);

}  // namespace penumbra::bench
