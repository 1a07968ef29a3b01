// Ground truth for shadows: a ray marched from the sample to the light through the volume with
// the camera's sample distance and the same opacity correction. Mirrors the CPU reference.

#include "include/labels.glsl"

float shadow_ray_transmittance(vec3 world) {
    vec3 to_light = direction_to_light(world);
    float t_end = intersect_region(world, to_light, REGION_LIGHT).y;
#if POINT_LIGHT
    t_end = min(t_end, distance(u.light_vector.xyz, world));
#endif
    if (t_end <= 0.0) return 1.0;
    int count = int(max(1.0, ceil(t_end / settings.sample_distance)));
    float step_length = t_end / float(count);
    float transmittance = 1.0;
#if EMPTY_SPACE_SKIPPING
    // As the camera rays do (classify_sample in raycast.glsl): up to this distance the bricks are
    // known to be occupied, so the grid is looked at once per brick, not once per sample. A
    // sample just past a face by rounding is looked at again, which can only keep a sample, and
    // every sample of an empty brick is exactly transparent: the result is the same to the bit.
    float occupied_until = -1.0;
#endif
#if PREINTEGRATION
    // Segments end to end from the lit point, [i, i + 1] steps, as the light slabs' are: the ray
    // counts [0, t_end] once, as the per-sample ray does with each sample standing for the step
    // around it. (A first sample classified alone for the step [0, 1] and segments between the
    // samples after it counted [1/2, 1] twice and left the last half step out: a darkening of
    // half a step's depth on every lit point inside tissue, which no finer step removed.) A
    // segment's label and brick are those of its middle, the per-sample ray's sample.
    float front = sample_value(world);
#endif
    for (int i = 0; i < count && transmittance >= negligible_transmittance; ++i) {
        float t = (float(i) + 0.5) * step_length;
        vec3 p = world + t * to_light;
#if EMPTY_SPACE_SKIPPING
        if (t >= occupied_until) {
            ivec3 brick = brick_of(p);
            float run = distance_out_of_brick(p, to_light, brick);
            if (!brick_occupied(brick)) {
                int last_in_brick = max(i + 1, i + int(ceil(run / step_length))) - 1;
#if PREINTEGRATION
                // The segment may come from an occupied brick, and the last one in this brick may
                // leave it: both are classified; those between lie in the empty brick (it is
                // convex) and are transparent.
                float back = sample_value(world + float(i + 1) * step_length * to_light);
                transmittance *=
                        1.0 - sample_opacity(in_label(classify_segment(front, back), p).a,
                                             step_length);
                front = last_in_brick > i
                                ? sample_value(world + float(last_in_brick) * step_length * to_light)
                                : back;
                i = max(i, last_in_brick - 1);
#else
                i = last_in_brick;
#endif
                continue;
            }
            occupied_until = t + run;
        }
#endif
#if PREINTEGRATION
        float back = sample_value(world + float(i + 1) * step_length * to_light);
        transmittance *=
                1.0 - sample_opacity(in_label(classify_segment(front, back), p).a, step_length);
        front = back;
#else
        transmittance *= 1.0 - sample_opacity(in_label(classify(sample_value(p)), p).a, step_length);
#endif
    }
    return transmittance;
}
