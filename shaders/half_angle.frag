// Half-angle slicing. Eye pass: the slice's premultiplied colour, lit by the light buffer as it
// stands after the slices nearer the light, blended into the eye buffer (front to back with
// "under", or back to front with "over"). Light pass: the slice's transmittance multiplied into
// the light buffer. Opacity is corrected for each ray's path through the slab.
//   HALF_ANGLE_LIGHT_PASS 0|1, PHONG 0|1, EXTINCTION 0|1, POINT_LIGHT 0|1, LABELS 0|1
#include "include/uniforms.glsl"
#include "include/volume.glsl"
#include "include/transfer_function.glsl"
#include "include/labels.glsl"
#include "include/compositing.glsl"
#include "include/shading.glsl"
#include "include/light_slab.glsl"
#include "include/light_view.glsl"

layout(binding = 3) uniform sampler2D half_angle_light;

in vec3 slice_world;
layout(location = 0) out vec4 result;

void main() {
    vec3 world = clamp_to_box(slice_world);
    vec3 axis = u.half_angle_axis.xyz;
    float spacing = u.half_angle_axis.w;
#if HALF_ANGLE_LIGHT_PASS
    vec3 travel = light_travel_at(world);
    float path_length = spacing / max(dot(axis, travel), 1e-3);
    // One point per slice, as Kniss et al. slice: the eye pass samples the same point (where a cut
    // face crosses the slab, the light's point is the middle of the part kept).
    result = vec4(slab_transmittance(world, travel, path_length, 1));
#else
    // The eye pass's slices are cut exactly to what camera rays keep (HalfAngleSlicer::cut_slices):
    // what the cut removed is not drawn; the light pass above decides what it shadows.
    vec3 ray = normalize(world - u.eye.xyz);
    float path_length = spacing / max(abs(dot(axis, ray)), 1e-3);
    float value = sample_value(world);
    vec4 classified = in_label(classify(value), world);
    float alpha = sample_opacity(classified.a, path_length);
    vec2 terms = vec2(1.0, 0.0);
#if PHONG
    vec3 gradient = value_gradient(world);
    if (u.region_counts.x > 0) gradient = gradient_at_cut(world, gradient, value);
    vec3 normal = normal_from_gradient(gradient);
    terms = blinn_phong(normal, direction_to_light(world), -ray);
#endif
    float light = texture(half_angle_light, light_uv(world)).r;
    result = vec4(shade(classified.rgb, terms, light) * alpha, alpha);
#endif
}
