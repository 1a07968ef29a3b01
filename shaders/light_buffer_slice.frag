// Builder A: the slice's transmittance, multiplied into the framebuffer by blending
// (GL_ZERO, GL_SRC_COLOR); the framebuffer is then copied into the next layer.
#include "include/uniforms.glsl"
#include "include/volume.glsl"
#include "include/transfer_function.glsl"
#include "include/compositing.glsl"
#include "include/light_slab.glsl"
#include "include/light_view.glsl"

in vec3 slice_world;
layout(location = 0) out vec4 transmittance;

void main() {
    vec3 ray = light_travel_at(slice_world);
    float path_length = u.light_slicing.w / dot(u.light_travel.xyz, ray);
    // The polygon is the slice's intersection with the box.
    vec3 inside = clamp_to_box(slice_world);
    transmittance =
            vec4(slab_transmittance(inside, ray, path_length, int(u.light_buffer_info.y)));
}
