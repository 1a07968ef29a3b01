#pragma once

// The optimisation table of `penumbra bench modes`: what each optimisation buys in each mode,
// measured by turning it off in the same run (empty-space skipping per frame, and for the
// light-buffer build; gradients from central differences against the gradient texture).

#include <penumbra/base/result.hpp>
#include <penumbra/bench/mode_bench.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/volume/label_map.hpp>
#include <penumbra/volume/volume.hpp>

#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::bench {

// One mode with empty-space skipping on and off.
struct SkippingRow {
    std::string label;  // "dvr", "sbrc cached", "sbrc cached, no phong"
    Series on;          // the whole frame and its raycast pass
    Series off;
    double psnr = 0.0;  // between the last images of the two series
};

// One mode without a cut, with planes that cut off only air at the box's corners (the same image:
// what asking the region costs per frame) and with a crop that keeps half of it (what a cut saves).
struct CutRow {
    std::string label;
    Series uncut;
    Series corners;
    Series half;
    double psnr = 0.0;  // between the uncut and the corners' images
};

// One mode drawing the scan alone, with a label map inside it (every label shown in its colour)
// and with a fifth of its labels hidden: what the overlay costs per frame.
struct LabelRow {
    std::string label;
    Series alone;
    Series labelled;
    Series hidden;
};

// The label table: each mode's rows; the light-buffer pass alone without and with the labels; and
// the builds that a visibility change and a camera move cause, counted over `repeat` frames each.
struct LabelTable {
    std::vector<LabelRow> rows;
    std::optional<Measurement> build_alone;
    std::optional<Measurement> build_labelled;
    std::uint64_t builds_per_visibility_change = 0;
    std::uint64_t builds_per_camera_move = 0;
    int changes = 0;
    // A pick through the view's middle (reference::pick, one ray on the CPU) against the cheapest
    // labelled frame: the median of as many picks as frames.
    double pick_ms = 0.0;
    double cheapest_labelled_frame_ms = 0.0;
};

struct OptimisationTable {
    std::vector<SkippingRow> rows;
    // The light-buffer pass alone, rebuilt every frame; absent unless sbrc is among the modes.
    std::optional<Measurement> build_on;
    std::optional<Measurement> build_off;
    std::vector<CutRow> cut_rows;
    // The light-buffer pass alone without a cut and with the half crop (cut tissue casting no
    // shadow, so the light meets half the volume); absent unless sbrc is among the modes.
    std::optional<Measurement> build_uncut;
    std::optional<Measurement> build_half;
};

// Each of `modes` but half_angle (which casts no rays) with skipping on and off, the shadow modes
// with Blinn-Phong as the targets measure them and sbrc once more without; the light
// buffer cached between timed frames. Then every mode of `modes` uncut, with a crop that keeps the
// whole volume and with one that keeps its half toward the patient's right. Prints each row to
// `out` as it is measured.
base::Result<OptimisationTable> measure_optimisations(ModeBench& bench,
                                                      const std::vector<scene::Mode>& modes,
                                                      const volume::Volume& volume, std::FILE* out);

// The label table for `labels`, which the bench's renderer holds beside `volume`
// (Renderer::set_labels). Prints each row to `out` as it is measured.
base::Result<LabelTable> measure_labels(ModeBench& bench, render::Renderer& renderer,
                                        const std::vector<scene::Mode>& modes,
                                        const volume::Volume& volume,
                                        const volume::LabelMap& labels, std::FILE* out);

struct GradientComparison {
    Series central;  // phong, gradients from central differences
    Series texture;  // phong, gradients from the precomputed texture
    double texture_build_ms = 0.0;
    double psnr = 0.0;  // between the two images
};

// Phong with each gradient source in a renderer of its own (the source is the renderer's
// choice), each created after the last is gone. A renderer's GL context is current on its thread
// from its creation, so no other renderer may be alive on this thread.
base::Result<GradientComparison> compare_gradients(
        const std::shared_ptr<const volume::Volume>& volume, const scene::FrameRequest& request,
        int repeat, std::FILE* out);

}  // namespace penumbra::bench
