#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/render/frame.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/volume/volume.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace penumbra::render {

struct RendererOptions {
    std::filesystem::path shader_dir;  // empty: the default search (gpu::default_shader_dir)
    bool debug_context = false;        // GL debug output routed to the log
    // Volume textures stay on the GPU, least recently used evicted first, while they fit this.
    std::size_t volume_memory_budget = std::size_t{2} << 30;
    // Light buffers stay cached by their inputs (volume, TF, light, n, R, builder, compositing,
    // compensation), least recently used evicted first, while they fit this.
    std::size_t light_buffer_memory_budget = std::size_t{1} << 30;
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
    // Mesa's software rasterisers (llvmpipe, softpipe): no GPU found, frames are drawn on the CPU.
    bool software = false;
    // False on Mesa's software rasterisers, whose timer queries do not measure compute dispatches
    // and return garbage for draws; pass times then carry gpu_ms = -1 and only wall times count.
    bool gpu_timer_queries = true;
    // Mesa's llvmpipe stops a shader invocation after 65535 loop iterations in all (its
    // LP_MAX_TGSI_LOOP_ITERATIONS); the compute ray caster then marches long rays in several
    // dispatches. 0 = no such limit.
    int max_shader_loop_iterations = 0;
};

// What the scheduler renders through, so that scheduling can be tested with a fake.
class FrameRenderer {
public:
    virtual ~FrameRenderer() = default;

    [[nodiscard]] virtual const RendererInfo& info() const = 0;

    virtual base::Status set_volume(std::shared_ptr<const volume::Volume> volume) = 0;

    virtual base::Result<Frame> render(const scene::FrameRequest& request) = 0;

    // Bytes of GPU memory held by cached volume textures and light buffers.
    [[nodiscard]] virtual std::size_t gpu_bytes_held() const = 0;
};

// The GPU renderer. It owns the headless GL context, so it is created, used and destroyed on one
// thread. GPU objects are cached by what they depend on: volume textures (several, LRU under a
// memory budget), the TF table until the TF changes, the light buffer until its inputs change,
// compiled shader variants for the renderer's life.
class Renderer final : public FrameRenderer {
public:
    static base::Result<std::unique_ptr<Renderer>> create(const RendererOptions& options = {});

    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;
    ~Renderer();

    [[nodiscard]] const RendererInfo& info() const override;

    // Makes the volume current, uploading it unless its texture is still cached, without losing
    // 16-bit/float precision.
    base::Status set_volume(std::shared_ptr<const volume::Volume> volume) override;

    // Renders one frame of the current volume in any mode of DESIGN.md §1.
    base::Result<Frame> render(const scene::FrameRequest& request) override;

    [[nodiscard]] std::size_t gpu_bytes_held() const override;

    // How many times the light attenuation buffer was built since the renderer was created.
    [[nodiscard]] std::uint64_t light_buffer_builds() const;

    struct LightBufferContents {
        int slices = 0;
        int resolution = 0;
        std::vector<float> values;  // layer after layer, R x R each, rows bottom-up
    };

    // The light buffer the last light-buffer frame used (for tests and tools).
    base::Result<LightBufferContents> read_light_buffer() const;

    // The paper's inset image: the last light-buffer layer after an sbrc frame, or the final
    // light buffer after a half_angle frame.
    base::Result<base::ImageRgba8> light_inset() const;

private:
    struct Impl;
    explicit Renderer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra::render
