#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/render/frame.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/volume/volume.hpp>

#include <filesystem>
#include <memory>
#include <string>

namespace penumbra::render {

struct RendererOptions {
    std::filesystem::path shader_dir;  // empty: the default search (gpu::default_shader_dir)
    bool debug_context = false;        // GL debug output routed to the log
};

// What the renderer runs on, for logs, CLI output and the protocol's hello.
struct RendererInfo {
    std::string platform;
    std::string vendor;
    std::string renderer;
    std::string version;
    int max_3d_texture_size = 0;
    int max_texture_size = 0;
    int max_array_texture_layers = 0;
};

// The GPU renderer. It owns the headless GL context, so it is created, used and destroyed on one
// thread. GPU objects are cached by what they depend on: the volume texture until another volume
// is set, the TF table until the TF changes, compiled shader variants for the renderer's life.
class Renderer {
public:
    static base::Result<std::unique_ptr<Renderer>> create(const RendererOptions& options = {});

    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;
    ~Renderer();

    [[nodiscard]] const RendererInfo& info() const;

    // Uploads the volume (once per distinct volume object) without losing 16-bit/float precision.
    base::Status set_volume(std::shared_ptr<const volume::Volume> volume);

    // Renders one frame of the current volume. Modes not implemented by this renderer return an
    // Error with code "unsupported_mode".
    base::Result<Frame> render(const scene::FrameRequest& request);

private:
    struct Impl;
    explicit Renderer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra::render
