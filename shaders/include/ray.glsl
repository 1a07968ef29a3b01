// Ray set-up; mirrors server/optics/include/penumbra/optics/ray.hpp.

// Where the whole line origin + t * direction crosses the volume box (slab method), t of either
// sign; x > y when it misses. Computed in box space, where the box is axis-aligned: distances
// along the line stay the same there.
vec2 intersect_line_box(vec3 world_origin, vec3 world_direction) {
    vec3 origin = mat3(u.world_to_box) * world_origin;
    vec3 direction = mat3(u.world_to_box) * world_direction;
    vec3 inverse = 1.0 / direction;
    vec3 t0 = (u.box_min.xyz - origin) * inverse;
    vec3 t1 = (u.box_max.xyz - origin) * inverse;
    vec3 t_small = min(t0, t1);
    vec3 t_large = max(t0, t1);
    // An axis-parallel ray starting on a slab plane gives NaN, which max/min below ignore the
    // same way the C++ version skips it: GLSL's max(x, NaN) is undefined, so test explicitly.
    float t_near = -3.0e38;
    float t_far = 3.0e38;
    for (int axis = 0; axis < 3; ++axis) {
        if (!isnan(t_small[axis])) t_near = max(t_near, t_small[axis]);
        if (!isnan(t_large[axis])) t_far = min(t_far, t_large[axis]);
    }
    return vec2(t_near, t_far);
}

// Entry and exit of the ray with the volume box. x = t_near (>= 0), y = t_far.
vec2 intersect_box(vec3 origin, vec3 direction) {
    vec2 line = intersect_line_box(origin, direction);
    return vec2(max(0.0, line.x), line.y);
}

// Where in its first step a ray takes its first sample, as a fraction of the step: the step's
// midpoint without jitter; with it, interleaved gradient noise over the pixels (neighbours differ
// by far more than a step's fraction, so fixed-step rings become fine noise) shifted by the golden
// ratio per pattern index, so that successive refinement steps cover the step evenly.
float ray_start_offset(ivec2 pixel) {
    if (u.jitter.x <= 0.0) return 0.5;
    // A tile's pixel takes the noise of its pixel in the whole image.
    vec2 image_pixel = vec2(pixel + u.image_size.zw);
    float noise = fract(52.9829189 * fract(dot(image_pixel, vec2(0.06711056, 0.00583715))));
    return fract(noise + u.jitter.y * 0.6180339887);
}

// The ray through the centre of pixel `pixel`, row 0 at the top of the image.
vec3 pixel_ray_direction(ivec2 pixel) {
    vec2 size = vec2(u.image_size.xy);
    float ndc_x = (float(pixel.x) + 0.5) / size.x * 2.0 - 1.0;
    float ndc_y = 1.0 - (float(pixel.y) + 0.5) / size.y * 2.0;
    return normalize(u.camera_forward.xyz + ndc_x * u.camera_right.xyz + ndc_y * u.camera_up.xyz);
}
