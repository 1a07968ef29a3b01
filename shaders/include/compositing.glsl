// Mirrors server/optics/include/penumbra/optics/compositing.hpp.
// EXTINCTION (0|1): read TF opacity as an extinction coefficient (paper eq. 6) instead of
// correcting it for the step length.

// Light dimmed below this fraction cannot matter to an 8-bit image: rays toward the light stop
// there.
const float negligible_transmittance = 1e-4;

float sample_opacity(float alpha, float step_length) {
    float unit = settings.opacity_unit_distance;
#if EXTINCTION
    return 1.0 - exp(-clamp(alpha, 0.0, 1.0) / unit * step_length);
#else
    return 1.0 - pow(1.0 - clamp(alpha, 0.0, 1.0), step_length / unit);
#endif
}

void composite_front_to_back(inout vec4 dst, vec3 color, float alpha) {
    float weight = (1.0 - dst.a) * alpha;
    dst.rgb += weight * color;
    dst.a += weight;
}
