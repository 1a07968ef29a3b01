// Lookup of the light attenuation buffer; mirrors server/optics light_slicing.hpp.
// Layer k of the array holds the transmittance from the light to slice k's plane.
#include "include/light_view.glsl"
#include "include/light_slab.glsl"

layout(binding = 2) uniform sampler2DArray light_buffer_texture;

// Paper eq. 8: the continuous slice index of a world point.
float light_slice_index(vec3 world) {
    return u.light_slicing.z * (dot(u.light_travel.xyz, world) - u.light_slicing.x) /
           (u.light_slicing.y - u.light_slicing.x);
}

// Transmittance from the light to `world`, interpolated between the two nearest layers (array
// textures filter within a layer only).
float light_transmittance(vec3 world) {
    float last = u.light_slicing.z - 1.0;
    float position = clamp(light_slice_index(world) - 0.5, 0.0, last);
    float lower = floor(position);
    float upper = min(lower + 1.0, last);
    vec2 uv = light_uv(world);
    float a = texture(light_buffer_texture, vec3(uv, lower)).r;
    float b = texture(light_buffer_texture, vec3(uv, upper)).r;
    return mix(a, b, position - lower);
}

// Transmittance from the light to `world`: the layer at the slab face nearer the light, times
// the material between that face and `world`, sampled the way the builders sample a slab, its
// points tested against the first `half_spaces` of the light's (sampled_slab_opacity).
// Interpolating between layers spreads a surface's own shadow over the whole slab, which shows
// as rings of the slice spacing on lit surfaces; this keeps the shadow where the surface is.
float light_transmittance_local(vec3 world, int half_spaces) {
    float index = clamp(light_slice_index(world), 0.0, u.light_slicing.z);
    float last = u.light_slicing.z - 1.0;
    float layer = min(floor(index), last);
    vec2 uv = light_uv(world);
    float before = texture(light_buffer_texture, vec3(uv, layer)).r;
    float inside = index - layer;  // of the slab, in slabs
    if (inside <= 0.0 || before <= 0.0) return before;
    // A slab that hardly dims the light holds no surface to misplace: interpolating is as good
    // as marching there, and most lit samples are in such slabs.
    float after = texture(light_buffer_texture, vec3(uv, min(layer + 1.0, last))).r;
    if (after >= 0.98 * before) return mix(before, after, inside);
    vec3 travel = light_travel_at(world);
    float depth = inside * u.light_slicing.w / dot(u.light_travel.xyz, travel);
    int samples = max(1, int(ceil(u.light_buffer_info.y * inside)));
    // No look at the bricks: the stretch ends at `world`, a visible sample, so its brick is
    // occupied and the stretch never lies in empty bricks only.
    float alpha = sampled_slab_opacity(world - 0.5 * depth * travel, travel, depth, samples,
                                       half_spaces);
    return before * slab_transmittance_of(alpha);
}

// The light a camera sample receives, read the way LOCAL_LIGHT_LOOKUP (0|1) asks; `half_spaces`
// as for light_transmittance_local.
float light_at_sample(vec3 world, int half_spaces) {
#if LOCAL_LIGHT_LOOKUP
    return light_transmittance_local(world, half_spaces);
#else
    return light_transmittance(world);
#endif
}
