#pragma once

#include <penumbra/base/image.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace penumbra::render {

// One pass that ran for a frame. `gpu_ms` comes from a GL timer query (0 for passes that issue no
// GPU work or are not timed, -1 where the GL implementation's timer queries mean nothing);
// `wall_ms` is CPU-side. Where timer queries mean nothing (llvmpipe, whose timers do not cover
// compute dispatches) the renderer waits for each pass, and `wall_ms` runs from issuing it until
// the GPU finished it: the figure to trust there. Where they work, nothing waits on the way
// (frames are pipelined): a pass's `wall_ms` is the time to issue it, and `readback`'s includes
// the wait for the frame's fence (Renderer::complete); either way a frame's wall times add up to
// the time the render thread spent on it, and measured_ms is the pass's own cost.
struct PassTiming {
    std::string name;
    double gpu_ms = 0.0;
    double wall_ms = 0.0;
};

// What a pass cost: its GPU time where a timer measured it, else its wall time.
[[nodiscard]] inline double measured_ms(const PassTiming& pass) {
    return pass.gpu_ms > 0.0 ? pass.gpu_ms : pass.wall_ms;
}

// What a frame did with the light buffer: `none` (the mode casts no light-buffer shadows),
// `built`, or `reused` (its inputs had not changed since it was last built: camera moves never
// rebuild it).
enum class LightBufferState { none, built, reused };

// The name the frame header and the CLI print ("none", "built", "reused").
[[nodiscard]] std::string_view to_string(LightBufferState state);

struct FrameReport {
    std::vector<PassTiming> passes;
    std::string variant;  // the shader variant's defines, e.g. "PHONG=1 EXTINCTION=0"
    std::string stage;    // "compute" or "fragment"
    LightBufferState light_buffer = LightBufferState::none;
    // Progressive stills: how many refinement steps the image holds beyond the still frame.
    int refinement_step = 0;

    [[nodiscard]] double gpu_total_ms() const;
};

struct Frame {
    base::ImageRgba8 image;  // opaque, rows top to bottom
    FrameReport report;
};

}  // namespace penumbra::render
