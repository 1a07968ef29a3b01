#include "penumbra/gpu/fence.hpp"

#include <utility>

namespace penumbra::gpu {

Fence::Fence(Fence&& other) noexcept
    : sync_(std::exchange(other.sync_, nullptr)) {}

Fence& Fence::operator=(Fence&& other) noexcept {
    if (this != &other) {
        reset();
        sync_ = std::exchange(other.sync_, nullptr);
    }
    return *this;
}

Fence::~Fence() {
    reset();
}

void Fence::reset() {
    if (sync_ != nullptr) {
        glDeleteSync(sync_);
        sync_ = nullptr;
    }
}

void Fence::insert() {
    reset();
    sync_ = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    glFlush();
}

base::Status Fence::wait() {
    if (sync_ == nullptr) {
        return base::Ok{};
    }
    // Woken every 100 ms: a GPU that never gets there hangs the render thread either way, but a
    // debugger then sees where.
    constexpr GLuint64 kPollNanoseconds = 100'000'000;
    GLenum waited = GL_TIMEOUT_EXPIRED;
    while (waited == GL_TIMEOUT_EXPIRED) {
        waited = glClientWaitSync(sync_, GL_SYNC_FLUSH_COMMANDS_BIT, kPollNanoseconds);
    }
    reset();
    if (waited == GL_WAIT_FAILED) {
        return base::make_error(base::ErrorCode::gl_error, "waiting for the GPU failed", "gpu");
    }
    return base::Ok{};
}

}  // namespace penumbra::gpu
