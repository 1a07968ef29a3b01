// One declaration of what the C++ side derives each frame; mirrored field for field by
// server/render/src/uniforms.hpp (static_asserts there check the std140 offsets). The request's
// settings (each row of scene::kSettings that a frame carries) are the generated block `settings`:
// `settings.light_buffer_compensation`, `settings.sample_distance`, `settings.compositing ==
// SETTINGS_COMPOSITING_EXTINCTION`, `settings.background`.
#include "generated/settings.glsl"

layout(std140, binding = 0) uniform FrameUniforms {
    vec4 eye;               // xyz: camera position
    vec4 camera_forward;    // xyz: unit view direction
    vec4 camera_right;      // xyz: right * tan(fov/2) * aspect
    vec4 camera_up;         // xyz: up * tan(fov/2)
    vec4 box_min;           // xyz: volume box corner (world)
    vec4 box_max;           // xyz
    vec4 voxel_size;        // xyz: one voxel's size in world units
    vec4 background;        // rgb
    vec4 light_radiance;    // rgb: light colour * intensity
    vec4 light_vector;      // xyz: direction toward a directional light, or point-light position
    vec4 value_map;         // x: scale, y: offset: normalised value = texel * scale + offset
    ivec4 image_size;       // xy: output size in pixels; zw: a tile's top-left pixel in its image
    // The light attenuation buffer (light_buffer.glsl, light_buffer.comp, light_buffer_slice.*).
    mat4 light_view_projection;          // world -> light clip space (paper eq. 9)
    mat4 light_inverse_view_projection;
    vec4 light_travel;      // xyz: L, the direction light travels (unit); w: 1 for a point light
    vec4 light_slicing;     // x: min, y: max of L.V over the box corners (eq. 7), z: n, w: spacing
    vec4 light_buffer_info; // x: resolution R, y: points per slab (slab_samples resolved),
                            // z: the longest stretch a local lookup marches toward the light
    vec4 cone;              // x: tan(cone angle)
    // Half-angle slicing (half_angle.*).
    mat4 camera_view_projection;  // world -> camera clip space, image row 0 at the top
    vec4 half_angle_axis;         // xyz: slice axis h; w: slice spacing along h
    vec4 half_angle_range;        // x: min of h.V over the box corners
    // The volume's orientation (volume.glsl): box space, where the box is axis-aligned and its
    // axes follow the volume's index axes, to world space (RAS) and back.
    mat4 box_to_world;
    mat4 world_to_box;
    // Jittered ray starts (ray.glsl): x: 1 = on, y: the pattern's index (the refinement step).
    vec4 jitter;
    // The region drawn (region.glsl): the box cut down by half-spaces dot(xyz, p) + w >= 0.
    ivec4 region_counts;            // x: those camera rays clip by, y: those the light does
    vec4 region_half_spaces[12];    // optics::kMaxHalfSpaces
    // The label map (labels.glsl): world space to the map's voxel index space (voxel i's centre at i).
    mat4 world_to_label;
    vec4 labels;  // x: how much a label's colour replaces the transfer function's
} u;
