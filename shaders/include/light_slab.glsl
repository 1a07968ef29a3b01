// What one light slice does to the light crossing it, shared by both light-buffer builders and by
// half-angle slicing: the TF opacity at the slice point, corrected for the path length through
// the slab, and the paper's darkening compensation (1 + a)^c, never brightening past 1.

bool inside_box(vec3 world) {
    return all(greaterThanEqual(world, u.box_min.xyz)) && all(lessThanEqual(world, u.box_max.xyz));
}

float slab_transmittance(vec3 world, float path_length, float compensation) {
    if (!inside_box(world)) return 1.0;
    float alpha = sample_opacity(classify(sample_value(world)).a, path_length);
    // An opaque slice stays opaque: 0 * (1 + a)^c overflows to 0 * inf = NaN for large c.
    if (alpha >= 1.0) return 0.0;
    return min(1.0, (1.0 - alpha) * pow(1.0 + alpha, compensation));
}
