#pragma once

#include <penumbra/base/result.hpp>

#include <memory>
#include <string>

namespace penumbra::gpu {

struct ContextInfo {
    std::string platform;  // "EGL_EXT_platform_device" or "EGL_MESA_platform_surfaceless"
    std::string vendor;    // GL_VENDOR
    std::string renderer;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::string version;   // GL_VERSION
    int max_3d_texture_size = 0;
    int max_texture_size = 0;
    int max_array_texture_layers = 0;
};

struct ContextOptions {
    bool debug = false;  // a debug context, with GL debug messages routed to the log
};

// A headless OpenGL 4.5 core context on EGL, current on the thread that created it. EGL devices
// (EGL_EXT_platform_device) are tried first, so an NVIDIA GPU is used where one exists; Mesa's
// surfaceless platform (llvmpipe without a GPU) is the fallback. Move-only; destroying it
// releases the context and terminates the display.
class Context {
public:
    static base::Result<Context> create(const ContextOptions& options = {});

    Context(Context&&) noexcept;
    Context& operator=(Context&&) noexcept;
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;
    ~Context();

    [[nodiscard]] const ContextInfo& info() const;

    // Makes the context current on the calling thread (a context is current on one thread only).
    base::Status make_current() const;

private:
    struct State;
    explicit Context(std::unique_ptr<State> state);
    std::unique_ptr<State> state_;
};

}  // namespace penumbra::gpu
