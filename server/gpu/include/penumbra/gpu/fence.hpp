#pragma once

#include <penumbra/base/result.hpp>

#include <epoxy/gl.h>

namespace penumbra::gpu {

// A point in the GL command stream that the CPU can wait for: everything issued before
// insert() is done when wait() returns. Move-only; holds no fence until insert().
class Fence {
public:
    Fence() = default;
    Fence(const Fence&) = delete;
    Fence& operator=(const Fence&) = delete;
    Fence(Fence&& other) noexcept;
    Fence& operator=(Fence&& other) noexcept;
    ~Fence();

    // Puts the fence after the commands issued so far (replacing one not yet waited for) and
    // flushes them, so that the GPU reaches it while the CPU waits.
    void insert();

    [[nodiscard]] bool pending() const { return sync_ != nullptr; }

    // Waits until the GPU has passed the fence; at once when none is pending. Fails with gl_error
    // if the GL lost it.
    base::Status wait();

private:
    void reset();

    GLsync sync_ = nullptr;
};

}  // namespace penumbra::gpu
