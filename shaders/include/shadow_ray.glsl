// Ground truth for shadows: a ray marched from the sample to the light through the volume with
// the camera's sample distance and the same opacity correction. Mirrors the CPU reference.

float shadow_ray_transmittance(vec3 world) {
    vec3 to_light = direction_to_light(world);
    float t_end = intersect_box(world, to_light).y;
#if POINT_LIGHT
    t_end = min(t_end, distance(u.light_vector.xyz, world));
#endif
    if (t_end <= 0.0) return 1.0;
    int count = int(max(1.0, ceil(t_end / settings.sample_distance)));
    float step_length = t_end / float(count);
    float transmittance = 1.0;
    for (int i = 0; i < count && transmittance >= negligible_transmittance; ++i) {
        vec3 p = world + (float(i) + 0.5) * step_length * to_light;
#if EMPTY_SPACE_SKIPPING
        int next = next_sample_outside_empty(p, to_light, i, step_length);
        if (next != i) {
            i = next - 1;
            continue;
        }
#endif
        transmittance *= 1.0 - sample_opacity(classify(sample_value(p)).a, step_length);
    }
    return transmittance;
}
