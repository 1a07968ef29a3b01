#pragma once

#include <penumbra/gpu/objects.hpp>

namespace penumbra::gpu {

// Measures the GPU time of the commands between begin() and end() with a GL_TIME_ELAPSED query.
// Reading the result waits for those commands to finish, so read after the frame is submitted.
class GpuTimer {
public:
    GpuTimer();

    void begin();
    void end();

    // Milliseconds between begin() and end(); waits for the result.
    [[nodiscard]] double milliseconds() const;

private:
    Query query_;
};

}  // namespace penumbra::gpu
