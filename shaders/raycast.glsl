// THE march loop: one source for every ray-cast mode; effects are compiled in or out by defines.
//
// Defines (injected by the renderer; see shaders/README.md):
//   PHONG        0|1  Blinn–Phong shading from central-difference gradients
//   EXTINCTION   0|1  extinction compositing (paper eq. 6) instead of corrected alpha
//   POINT_LIGHT  0|1  the light is a point at light_vector rather than a direction

#include "include/uniforms.glsl"
#include "include/ray.glsl"
#include "include/volume.glsl"
#include "include/transfer_function.glsl"
#include "include/compositing.glsl"
#include "include/shading.glsl"

// Front-to-back emission–absorption along the ray of `pixel`, composited over the background.
vec4 march(ivec2 pixel) {
    vec3 origin = u.eye.xyz;
    vec3 direction = pixel_ray_direction(pixel);
    vec2 hit = intersect_box(origin, direction);
    vec4 accumulated = vec4(0.0);
    float length_inside = hit.y - hit.x;
    if (length_inside > 0.0) {
        // Equal steps no longer than the sample distance, sampled at their midpoints.
        int count = int(max(1.0, ceil(length_inside / u.march.x)));
        float step_length = length_inside / float(count);
        for (int i = 0; i < count; ++i) {
            vec3 position = origin + (hit.x + (float(i) + 0.5) * step_length) * direction;
            vec4 classified = classify(sample_value(position));
            if (classified.a <= 0.0) continue;
            vec3 color = classified.rgb;
#if PHONG
            vec3 normal = normal_from_gradient(value_gradient(position));
            color = shade(color, blinn_phong(normal, direction_to_light(position), -direction));
#endif
            composite_front_to_back(accumulated, color, sample_opacity(classified.a, step_length));
            if (accumulated.a >= u.march.z) break;
        }
    }
    return vec4(accumulated.rgb + (1.0 - accumulated.a) * u.background.rgb, 1.0);
}
