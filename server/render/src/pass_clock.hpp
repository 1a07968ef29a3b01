#pragma once

#include <penumbra/gpu/commands.hpp>
#include <penumbra/gpu/timer.hpp>

#include <chrono>

namespace penumbra::render {

// The wall-clock times of passes that FrameReport records (PassTiming::wall_ms).
using Clock = std::chrono::steady_clock;

inline double milliseconds_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The time since `start` once the GPU has finished what was issued: the wall time of a pass that
// runs once per volume.
inline double finished_ms_since(Clock::time_point start) {
    gpu::finish();
    return milliseconds_since(start);
}

// The wall time of a pass on a frame's path (a table or light buffer rebuilt when a setting
// changes, a still's accumulation). Where timer queries time the GPU (`timer_queries`,
// RendererInfo::gpu_timer_queries) the renderer does not wait for it, which would drain the
// frames in flight behind it: this is the time to issue it, its timer has its GPU time, and the
// frame's fence (Renderer::complete) its end. Elsewhere wall times are the only measure: the
// time until the GPU finished it.
inline double pass_ms_since(Clock::time_point start, bool timer_queries) {
    return timer_queries ? milliseconds_since(start) : finished_ms_since(start);
}

// A pass's GPU time from its timer, or -1 where the device's timer queries mean nothing
// (RendererInfo::gpu_timer_queries).
inline double gpu_ms(const gpu::GpuTimer& timer, bool timer_queries) {
    return timer_queries ? timer.milliseconds() : -1.0;
}

}  // namespace penumbra::render
