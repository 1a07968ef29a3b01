#pragma once

#include "frame_geometry.hpp"

#include <penumbra/gpu/objects.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <array>
#include <cstddef>

namespace penumbra::render {

// Mirrors the FrameUniforms block of shaders/include/uniforms.glsl (std140: every member here is
// a vec4 or ivec4, so the C++ layout matches without padding rules). What the frame derives: the
// camera, the box, the light's view, resolved counts. The request's numeric settings themselves
// reach the shaders through the generated Settings block (settings_block.hpp), not through here.
struct FrameUniforms {
    glm::vec4 eye;
    glm::vec4 camera_forward;
    glm::vec4 camera_right;
    glm::vec4 camera_up;
    glm::vec4 box_min;
    glm::vec4 box_max;
    glm::vec4 voxel_size;
    glm::vec4 background;
    glm::vec4 light_radiance;
    glm::vec4 light_vector;
    glm::vec4 value_map;
    glm::ivec4 image_size;
    glm::mat4 light_view_projection;
    glm::mat4 light_inverse_view_projection;
    glm::vec4 light_travel;
    glm::vec4 light_slicing;
    glm::vec4 light_buffer_info;
    glm::vec4 cone;
    glm::mat4 camera_view_projection;
    glm::vec4 half_angle_axis;
    glm::vec4 half_angle_range;
    glm::mat4 box_to_world;
    glm::mat4 world_to_box;
    glm::vec4 jitter;
    glm::ivec4 region_counts;  // x: the half-spaces camera rays clip by, y: those the light does
    std::array<glm::vec4, optics::kMaxHalfSpaces> region_half_spaces;  // xyz: normal, w: offset
    glm::mat4 world_to_label;  // the label map's voxel index space (identity without one)
    glm::vec4 labels;          // x: how much a label's colour replaces the TF's
};

static_assert(offsetof(FrameUniforms, eye) == 0);
static_assert(offsetof(FrameUniforms, box_min) == 64);
static_assert(offsetof(FrameUniforms, light_radiance) == 128);
static_assert(offsetof(FrameUniforms, value_map) == 160);
static_assert(offsetof(FrameUniforms, image_size) == 176);
static_assert(offsetof(FrameUniforms, light_view_projection) == 192);
static_assert(offsetof(FrameUniforms, light_travel) == 320);
static_assert(offsetof(FrameUniforms, light_buffer_info) == 352);
static_assert(offsetof(FrameUniforms, camera_view_projection) == 384);
static_assert(offsetof(FrameUniforms, box_to_world) == 480);
static_assert(offsetof(FrameUniforms, jitter) == 608);
static_assert(offsetof(FrameUniforms, region_counts) == 624);
static_assert(offsetof(FrameUniforms, region_half_spaces) == 640);
static_assert(offsetof(FrameUniforms, world_to_label) == 640 + 16 * optics::kMaxHalfSpaces);
static_assert(sizeof(FrameUniforms) == 640 + 16 * optics::kMaxHalfSpaces + 64 + 16);

// The uniforms of `request` with its geometry, on a volume of `dims` voxels whose texels
// `value_map` turns into normalised values (VolumeTexture::value_map).
FrameUniforms frame_uniforms(const scene::FrameRequest& request, const FrameGeometry& g,
                             glm::uvec3 dims, glm::vec2 value_map);

// The frame's two uniform blocks on the GPU: FrameUniforms (binding 0) and the request's settings
// (the generated Settings block, settings_block.hpp).
class FrameBlocks {
public:
    FrameBlocks();

    // Uploads both and binds them for every pass that follows.
    void bind(const FrameUniforms& uniforms, const scene::FrameRequest& request) const;

private:
    gpu::Buffer uniforms_;
    gpu::Buffer settings_;
};

}  // namespace penumbra::render
