// Soft shadows from the light buffer; mirrors the scattering settings of server/scene.
// SCATTERING: SCATTERING_NONE, SCATTERING_SHELL or SCATTERING_CONE.

// Shell: the sample and its 6 axis neighbours at radius r, 2r, ... (rings); ring i weighs 1/i.
// `half_spaces` as for light_transmittance_local, for the sample's own lookup.
float shell_transmittance(vec3 world, int half_spaces) {
    float centre_weight = settings.scattering_shell_center_weight;
    int rings = settings.scattering_shell_rings;
    float ring_norm = 0.0;
    for (int ring = 1; ring <= rings; ++ring) ring_norm += 1.0 / float(ring);
    float sum = centre_weight * light_at_sample(world, half_spaces);
    for (int ring = 1; ring <= rings; ++ring) {
        float r = settings.scattering_shell_radius * float(ring);
        float w = (1.0 - centre_weight) / (float(ring) * ring_norm * 6.0);
        sum += w * (light_transmittance(world + vec3(r, 0, 0)) +
                    light_transmittance(world - vec3(r, 0, 0)) +
                    light_transmittance(world + vec3(0, r, 0)) +
                    light_transmittance(world - vec3(0, r, 0)) +
                    light_transmittance(world + vec3(0, 0, r)) +
                    light_transmittance(world - vec3(0, 0, r)));
    }
    return sum;
}

// Rodrigues' rotation of v about the unit axis k by angle theta (paper eq. 10).
vec3 rotate_about(vec3 v, vec3 k, float theta) {
    float c = cos(theta);
    return v * c + cross(k, v) * sin(theta) + k * dot(k, v) * (1.0 - c);
}

// Cone: 8 samples on a disc perpendicular to the light, one slice toward it. The disc's first
// axis lies in the plane of the sample, the light and the viewer (the paper's projection base),
// the others follow by rotating it about L in steps of 45 degrees. `half_spaces` as for
// light_transmittance_local, for the stretch between the disc and the sample.
float cone_transmittance(vec3 world, vec3 to_eye, int half_spaces) {
    vec3 travel = light_travel_at(world);
    float spacing = u.light_slicing.w;
    vec3 centre = world - travel * spacing;
    vec3 base = to_eye - dot(to_eye, travel) * travel;
    if (dot(base, base) < 1e-8) {
        base = cross(travel, abs(travel.z) < 0.9 ? vec3(0, 0, 1) : vec3(0, 1, 0));
    }
    base = normalize(base);
    float radius = spacing * u.cone.x;
    float sum = 0.0;
    for (int k = 0; k < 8; ++k) {
        vec3 axis = rotate_about(base, travel, float(k) * 0.78539816339);
        sum += light_transmittance(centre + radius * axis);
    }
    float scattered = mix(sum / 8.0, light_transmittance(centre), settings.scattering_cone_center_weight);
#if LOCAL_LIGHT_LOOKUP
    // The disc lies a slab toward the light; what lies between it and the sample still dims the
    // light, unscattered. No look at the bricks: the stretch ends at a visible sample, whose
    // brick is occupied.
    int samples = max(1, int(u.light_buffer_info.y));
    float alpha = sampled_slab_opacity(world - 0.5 * spacing * travel, travel, spacing, samples,
                                       half_spaces);
    scattered *= slab_transmittance_of(alpha);
#endif
    return scattered;
}
