#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/gpu/fence.hpp>
#include <penumbra/gpu/objects.hpp>

#include <cstddef>
#include <span>

namespace penumbra::gpu {

// Reads a texture back without stalling the GL: start() queues the copy into a pixel-pack buffer
// of its own, followed by a fence, and returns at once; wait() and read() wait for that fence
// only, so the commands issued after start() (the next frame) keep the GPU busy meanwhile.
class AsyncReadback {
public:
    // Queues the copy of level 0 of `texture`, converted to `format`/`type`, `bytes` in all.
    void start(const Texture& texture, GLenum format, GLenum type, std::size_t bytes);

    // Waits until the copy is done; fails with gl_error if the GL lost the fence.
    base::Status wait() { return fence_.wait(); }

    // Waits if need be, then copies the bytes into `out` (the size start() was given).
    base::Status read(std::span<std::byte> out);

private:
    Buffer buffer_;
    std::size_t capacity_ = 0;
    std::size_t bytes_ = 0;  // of the copy started last; 0: none, or read already
    Fence fence_;
};

}  // namespace penumbra::gpu
