#pragma once

#include "slice_geometry.hpp"

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/gpu/shader_library.hpp>
#include <penumbra/gpu/timer.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <map>
#include <string>
#include <vector>

namespace penumbra::render {

// The light attenuation buffer: a GL_TEXTURE_2D_ARRAY of n layers of R x R transmittances (R16F)
// seen from the light; layer k holds what reaches slice k. Both builders expect the frame's
// uniform block to be bound and the volume and TF textures on units 0 and 1.
class LightBuffer {
public:
    explicit LightBuffer(const gpu::ShaderLibrary& shaders);

    // Fills the buffer with `builder`. `slices` carries the polygons builder A draws; `defines`
    // is the compositing variant (EXTINCTION).
    base::Status build(scene::LightBufferBuilder builder, int slices, int resolution,
                       const SliceMesh& mesh, const gpu::Defines& defines, gpu::GpuTimer& timer);

    [[nodiscard]] GLuint texture() const { return layers_.name(); }

    [[nodiscard]] int slices() const { return slices_; }

    [[nodiscard]] int resolution() const { return resolution_; }

    // All layers as floats, layer after layer, rows bottom-up as GL stores them.
    [[nodiscard]] std::vector<float> read() const;

    // One layer as a grey image (white = fully lit), like the insets of the paper's figures.
    [[nodiscard]] base::ImageRgba8 layer_image(int layer) const;

private:
    void allocate(int slices, int resolution);
    base::Result<const gpu::Program*> program(const std::string& key, const gpu::Defines& defines,
                                              bool per_slice);
    base::Status build_per_slice(const SliceMesh& mesh, const gpu::Program& program);

    const gpu::ShaderLibrary& shaders_;
    std::map<std::string, gpu::Program> programs_;
    gpu::Texture layers_;
    gpu::Texture scratch_;  // builder A's framebuffer colour
    gpu::Framebuffer scratch_framebuffer_;
    int slices_ = 0;
    int resolution_ = 0;
};

}  // namespace penumbra::render
