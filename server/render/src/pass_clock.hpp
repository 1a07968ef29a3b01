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

// The time since `start` once the GPU has finished what was issued: a pass's wall time.
inline double finished_ms_since(Clock::time_point start) {
    gpu::finish();
    return milliseconds_since(start);
}

// A pass's GPU time from its timer, or -1 where the device's timer queries mean nothing
// (RendererInfo::gpu_timer_queries).
inline double gpu_ms(const gpu::GpuTimer& timer, bool timer_queries) {
    return timer_queries ? timer.milliseconds() : -1.0;
}

}  // namespace penumbra::render
