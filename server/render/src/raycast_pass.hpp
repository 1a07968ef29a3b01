#pragma once

#include "uniforms.hpp"

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/gpu/shader_library.hpp>
#include <penumbra/gpu/timer.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <map>
#include <string>

namespace penumbra::render {

// The effects one ray-cast variant compiles in; everything else is compiled out.
struct RaycastVariant {
    bool phong = false;
    bool extinction = false;
    bool point_light = false;
    scene::RaycastStage stage = scene::RaycastStage::compute;

    [[nodiscard]] gpu::Defines defines() const;
    [[nodiscard]] std::string key() const;  // "PHONG=1 EXTINCTION=0 POINT_LIGHT=0 compute"
};

// Runs shaders/raycast.{comp,frag} into an RGBA8 image and reads it back. Programs are compiled
// on first use of a variant and kept; the output image is re-created only when the size changes.
class RaycastPass {
public:
    explicit RaycastPass(const gpu::ShaderLibrary& shaders);

    // Expects the volume texture on unit 0 and the TF texture on unit 1.
    base::Status run(const RaycastVariant& variant, const FrameUniforms& uniforms,
                     gpu::GpuTimer& timer);

    // Reads the last image back into `image` (rows top to bottom).
    void read_back(base::ImageRgba8& image) const;

private:
    base::Result<const gpu::Program*> program_for(const RaycastVariant& variant);
    void ensure_target(int width, int height);

    const gpu::ShaderLibrary& shaders_;
    std::map<std::string, gpu::Program> programs_;
    gpu::Buffer uniform_buffer_;
    gpu::Texture target_;
    gpu::Framebuffer framebuffer_;
    gpu::VertexArray empty_vertex_array_;
    int width_ = 0;
    int height_ = 0;
};

}  // namespace penumbra::render
