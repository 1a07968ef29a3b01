#pragma once

#include "program_cache.hpp"
#include "slice_geometry.hpp"
#include "work_chunks.hpp"

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/gpu/shader_library.hpp>
#include <penumbra/gpu/timer.hpp>
#include <penumbra/optics/region.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <glm/vec4.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace penumbra::render {

// Everything a light buffer's content depends on, its key in the renderer's cache: the volume, the
// opacity the builders classify with (the baked TF's alpha channel, so a colour change reuses the
// buffer), and the request with what the builders are known not to read reset to its default.
// Every other member of the request stays in, so a setting added later rebuilds the buffer until
// it is shown not to matter, rather than serving stale shadows.
struct LightBufferInputs {
    std::uint64_t volume_generation = 0;
    std::vector<float> opacities;
    // The label map (0: none) and what its labels do to the light: their opacity scales (a
    // colour or blend change reuses the buffer).
    std::uint64_t labels_generation = 0;
    std::vector<float> label_opacities;
    scene::FrameRequest request;  // its cut left out: `light_cut` says what the light meets
    std::vector<optics::HalfSpace> light_cut;

    bool operator==(const LightBufferInputs&) const = default;
};

// The inputs of the buffer `request` reads, for the volume of `volume_generation` under the baked
// TF `table`, with the slab samples resolved, in `region` (the request's cut of that volume).
// `labels_generation` is the label map's the frame draws (0 without one).
LightBufferInputs light_buffer_inputs(const scene::FrameRequest& request,
                                      const optics::Region& region, std::uint64_t volume_generation,
                                      const std::vector<glm::vec4>& table, int slab_samples,
                                      std::uint64_t labels_generation);

// A light attenuation buffer: a GL_TEXTURE_2D_ARRAY of n layers of R x R transmittances (R16F)
// seen from the light; layer k holds what reaches slice k.
class LightBuffer {
public:
    LightBuffer(int slices, int resolution);

    [[nodiscard]] const gpu::Texture& texture() const { return layers_; }

    [[nodiscard]] int slices() const { return slices_; }

    [[nodiscard]] int resolution() const { return resolution_; }

    [[nodiscard]] std::size_t bytes() const { return bytes_for(slices_, resolution_); }

    // What a buffer of these dimensions holds on the GPU: one half float per texel.
    [[nodiscard]] static std::size_t bytes_for(int slices, int resolution) {
        return static_cast<std::size_t>(resolution) * static_cast<std::size_t>(resolution) *
               static_cast<std::size_t>(slices) * 2;
    }

    // All layers as floats, layer after layer, rows bottom-up as GL stores them.
    [[nodiscard]] std::vector<float> read() const;

    // One layer as a grey image (white = fully lit), like the insets of the paper's figures.
    [[nodiscard]] base::ImageRgba8 layer_image(int layer) const;

private:
    gpu::Texture layers_;
    int slices_;
    int resolution_;
};

// Fills light buffers with either builder. Expects the frame's uniform block bound and the
// volume and TF textures on units 0 and 1.
class LightBufferBuilder {
public:
    explicit LightBufferBuilder(ProgramCache& programs);

    // `mesh` carries the slice polygons builder A draws; `defines` is the compositing variant;
    // `slab_samples` the points each texel samples per slice, which sizes the chunks. Fails with
    // cancelled_error() when `chunks` says the frame was cancelled (the buffer is then partial).
    base::Status build(LightBuffer& target, scene::LightBufferBuilder builder,
                       const SliceMesh& mesh, const gpu::Defines& defines, int slab_samples,
                       gpu::GpuTimer& timer, WorkChunks& chunks);

private:
    base::Status build_per_slice(LightBuffer& target, const SliceMesh& mesh,
                                 const gpu::Program& program, double work_per_slice,
                                 WorkChunks& chunks);
    static base::Status build_multi_slice(LightBuffer& target, const gpu::Program& program,
                                          double work_per_texel, WorkChunks& chunks);

    ProgramCache& programs_;
    gpu::Texture scratch_;  // builder A's framebuffer colour
    gpu::Framebuffer scratch_framebuffer_;
    int scratch_resolution_ = 0;
};

}  // namespace penumbra::render
