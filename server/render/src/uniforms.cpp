#include "uniforms.hpp"

#include "settings_block.hpp"
#include "slice_geometry.hpp"

#include <penumbra/gpu/commands.hpp>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>
#include <span>

namespace penumbra::render {
namespace {

glm::vec4 v4(glm::dvec3 v, double w = 0.0) {
    return glm::vec4(glm::dvec4(v, w));
}

}  // namespace

FrameUniforms frame_uniforms(const scene::FrameRequest& request, const FrameGeometry& g,
                             glm::uvec3 dims, glm::vec2 value_map) {
    const scene::RenderSettings& s = request.settings;
    const scene::Box& box = g.box;
    const scene::CameraFrame camera = scene::pixel_frame(request);
    const scene::Light& light = request.light;
    FrameUniforms u{};
    u.eye = v4(camera.eye);
    u.camera_forward = v4(camera.forward);
    u.camera_right = v4(camera.right);
    u.camera_up = v4(camera.up);
    u.box_min = v4(box.min);
    u.box_max = v4(box.max);
    u.voxel_size = v4(box.size() / glm::dvec3(dims));
    u.box_to_world = glm::mat4(glm::mat3(box.axes));
    u.world_to_box = glm::mat4(glm::mat3(box.inverse_axes));
    u.background = v4(s.background, 1.0);
    u.light_radiance = v4(light.color * light.intensity);
    u.light_vector = v4(light.type == scene::LightType::point ? light.position
                                                              : glm::normalize(light.direction));
    u.value_map = glm::vec4(value_map, 0.0f, 0.0f);
    // A tile's pixels take the whole image's jitter offsets (ray_start_offset).
    u.image_size = glm::ivec4(s.width, s.height, request.tile.x, request.tile.y);
    // What the shaders need beyond the request's own settings (the Settings block): the
    // device-bound resolution, the slab samples resolved, the cone's tangent in double.
    u.light_buffer_info = glm::vec4(static_cast<float>(s.light_buffer.resolution),
                                    static_cast<float>(g.slab_samples), 0.0f, 0.0f);
    u.cone = glm::vec4(static_cast<float>(std::tan(glm::radians(s.scattering.cone_angle_degrees))),
                       0.0f, 0.0f, 0.0f);
    u.camera_view_projection = glm::mat4(camera_view_projection(request, box));
    if (g.light_view) {
        u.light_view_projection = glm::mat4(g.light_view->view_projection);
        u.light_inverse_view_projection = glm::mat4(g.light_view->inverse_view_projection);
        u.light_travel = v4(g.travel, g.light_view->perspective ? 1.0 : 0.0);
        const optics::LightSlicing& slicing = g.light_slicing;
        u.light_slicing =
                glm::vec4(static_cast<float>(slicing.min), static_cast<float>(slicing.max),
                          static_cast<float>(slicing.count), static_cast<float>(slicing.spacing()));
        // A local lookup marches at most one slab toward the light, along the light's ray: the
        // slice spacing, stretched by a point light's widest ray (and a thousandth, so that
        // rounding to float never makes it shorter).
        const double reach = g.light_view->perspective
                                     ? point_light_reach(g.box, g.light_view->position, g.travel)
                                     : 1.0;
        u.light_buffer_info.z = static_cast<float>(slicing.spacing() * reach * 1.001);
    }
    if (g.half_angle_axis != glm::dvec3(0.0)) {
        u.half_angle_axis = v4(g.half_angle_axis, g.half_angle_slicing.spacing());
        u.half_angle_range =
                glm::vec4(static_cast<float>(g.half_angle_slicing.min), 0.0f, 0.0f, 0.0f);
    }
    u.jitter = glm::vec4(s.jitter ? 1.0f : 0.0f, static_cast<float>(request.refinement.step), 0.0f,
                         0.0f);
    const optics::Region& region = g.region;
    u.region_counts = glm::ivec4(region.count, region.light_count, 0, 0);
    for (int i = 0; i < region.count; ++i) {
        const optics::HalfSpace& h = region.half_spaces[static_cast<std::size_t>(i)];
        u.region_half_spaces[static_cast<std::size_t>(i)] = v4(h.normal, h.offset);
    }
    u.world_to_label = glm::mat4(1.0f);
    return u;
}

FrameBlocks::FrameBlocks()
    : uniforms_(gpu::create_storage_buffer(sizeof(FrameUniforms)))
    , settings_(gpu::create_storage_buffer(settings_block_bytes())) {}

void FrameBlocks::bind(const FrameUniforms& uniforms, const scene::FrameRequest& request) const {
    gpu::upload(uniforms_, std::as_bytes(std::span(&uniforms, 1)));
    gpu::bind_uniform_buffer(0, uniforms_);
    gpu::upload(settings_, settings_block_data(request));
    gpu::bind_uniform_buffer(settings_block_binding, settings_);
}

}  // namespace penumbra::render
