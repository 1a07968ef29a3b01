// Pre-integrated classification (Engel, Kraus & Ertl 2001): a segment between two consecutive
// samples, front value sf and back value sb, is classified as a whole instead of by one sample,
// so a thin opaque value range that falls between two samples still counts.
//
// The TF's opacity is read as an optical depth per opacity_unit_distance, as sample_opacity reads
// it (alpha compositing: -ln(1 - a), extinction compositing: a). preintegration_table.comp stores
// per (sf, sb) the segment's average optical depth, the integral of the depth over [sf, sb]
// divided by sb - sf, and its depth-weighted average colour. A segment is then a homogeneous
// sample of that depth: its equivalent TF opacity goes through sample_opacity, the light slabs'
// compensation and everything else exactly as a classified sample does, so the run-time step
// length and both compositing modes keep working, and sf == sb is today's classification.
//
// What it neglects: the value is taken to change linearly along the segment, and the colour is
// averaged without the segment's own attenuation (the colour near the front would dim what lies
// behind it within the segment). Keeping that would make the table depend on the step length
// and the compositing of the pixel's ray, one table per length; for segments of a sample step or
// two the difference is the self-attenuation of one step, which is what per-sample compositing
// neglects too.
//
// A segment is lit and shaded at its middle (raycast.glsl), where its material is on average; the
// first, which starts on the region's face, at its sample (lit_before).
//
// Opacity correction: the equivalent opacity is corrected for the actual step length, like a
// sample's. The light slabs are segments end to end too (sampled_slab_opacity, light_slab.glsl);
// their darkening compensation (1 + a)^c applies to the slab's opacity whatever classified it:
// pre-integration changes what a slab absorbs, not the compensation.

#ifndef PREINTEGRATION
#define PREINTEGRATION 0
#endif

// Below this transmittance per opacity unit distance, an opacity of 1 keeps a finite depth
// (16.6): the table's averages stay finite and an opaque entry stays opaque to a float.
const float min_unit_transmittance = 5.9604645e-8;  // 2^-24

float optical_depth_of_opacity(float alpha) {
#if EXTINCTION
    return clamp(alpha, 0.0, 1.0);
#else
    return -log(max(1.0 - clamp(alpha, 0.0, 1.0), min_unit_transmittance));
#endif
}

float opacity_of_optical_depth(float depth) {
#if EXTINCTION
    return depth;
#else
    return 1.0 - exp(-depth);
#endif
}

#if PREINTEGRATION
layout(binding = 6) uniform sampler2D preintegration_table;

// The segment from `front` to `back` as one classified sample: average colour, equivalent TF
// opacity. Within one cell of the table its bilinear filter would blur the TF to the table's
// resolution, so there the TF at the segment's middle is mixed in, all of it at front == back
// (exactly classify(back) then), none of it one cell away: continuous, so that no segment
// changes abruptly with the rounding of its values.
vec4 classify_segment(float front, float back) {
    front = clamp(front, 0.0, 1.0);
    back = clamp(back, 0.0, 1.0);
    vec2 size = vec2(textureSize(preintegration_table, 0));
    vec4 middle = classify(0.5 * (front + back));
    float table_weight = min(1.0, abs(back - front) * (size.x - 1.0));
    if (table_weight == 0.0) return middle;
    vec4 entry = texture(preintegration_table, (vec2(front, back) * (size - 1.0) + 0.5) / size);
    entry = mix(vec4(middle.rgb, optical_depth_of_opacity(middle.a)), entry, table_weight);
    return vec4(entry.rgb, opacity_of_optical_depth(entry.a));
}
#endif
