// Lookup of the light attenuation buffer; mirrors server/optics light_slicing.hpp.
// Layer k of the array holds the transmittance from the light to slice k's plane.
#include "include/light_view.glsl"

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
