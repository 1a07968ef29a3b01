// Builds the pre-integration table (include/preintegration.glsl) from the TF table on unit 1,
// whenever the TF or the compositing changes.
//   STEP 0 (one invocation): cumulative[k] = the integral from 0 to entry k's centre of
//          (depth * colour, depth), the TF read as include/transfer_function.glsl's linear filter
//          reads it.
//   STEP 1 (one invocation per entry of the N x N table): entry (i, j), front i / (N - 1), back
//          j / (N - 1): the difference of the integral at the two values over their distance, so
//          a segment's average is exact whatever the value range of the volume (a 16-bit CT's
//          thin bone range included), up to the TF table's own resolution.
// The integrals between two TF entries by Simpson's rule over 32 parts: exact for extinction
// compositing (depth and colour are linear there, their product quadratic), close for alpha's
// -ln(1 - a).
// EXTINCTION (0|1): as the ray caster's.
#include "include/transfer_function.glsl"
#include "include/preintegration.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform writeonly image2D table_image;
layout(std430, binding = 0) buffer Cumulative {
    vec4 cumulative[];
};
layout(location = 0) uniform int step;

vec4 integrand(vec4 entry) {
    float depth = optical_depth_of_opacity(entry.a);
    return vec4(depth * entry.rgb, depth);
}

// The integral across fractions [0, to] of the interval from TF entry k to entry k + 1.
vec4 integral_from_entry(int k, float to) {
    const int parts = 32;
    vec4 a = texelFetch(transfer_function_texture, k, 0);
    vec4 b = texelFetch(transfer_function_texture, k + 1, 0);
    float h = to / float(parts);
    vec4 sum = integrand(a) + integrand(mix(a, b, to));
    for (int p = 1; p < parts; ++p) {
        sum += float(2 + 2 * (p & 1)) * integrand(mix(a, b, float(p) * h));
    }
    int entries = textureSize(transfer_function_texture, 0);
    return sum * (h / 3.0) / float(entries);
}

// The integral from 0 to the normalised value s. Outside the entries' centres the filter holds
// the end entries.
vec4 cumulative_at(float s) {
    int entries = textureSize(transfer_function_texture, 0);
    float x = s * float(entries) - 0.5;
    if (x <= 0.0) return integrand(texelFetch(transfer_function_texture, 0, 0)) * s;
    if (x >= float(entries - 1)) {
        return cumulative[entries - 1] +
               integrand(texelFetch(transfer_function_texture, entries - 1, 0)) *
                       ((x - float(entries - 1)) / float(entries));
    }
    int k = int(floor(x));
    return cumulative[k] + integral_from_entry(k, x - float(k));
}

void main() {
    int entries = textureSize(transfer_function_texture, 0);
    if (step == 0) {
        if (gl_GlobalInvocationID.xy != uvec2(0)) return;
        vec4 sum = integrand(texelFetch(transfer_function_texture, 0, 0)) * (0.5 / float(entries));
        for (int k = 0; k < entries; ++k) {
            cumulative[k] = sum;
            if (k + 1 < entries) sum += integral_from_entry(k, 1.0);
        }
        return;
    }
    ivec2 size = imageSize(table_image);
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(texel, size))) return;
    float front = float(texel.x) / float(size.x - 1);
    float back = float(texel.y) / float(size.y - 1);
    vec4 middle = classify(0.5 * (front + back));
    vec4 entry = vec4(middle.rgb, optical_depth_of_opacity(middle.a));
    if (texel.x != texel.y) {
        vec4 integral = cumulative_at(back) - cumulative_at(front);
        entry.a = max(integral.a / (back - front), 0.0);
        // A segment with (next to) no depth has no colour that matters, and its quotient would
        // be the rounding of two cumulative sums: the middle's colour stands in.
        if (integral.a / (back - front) > 1e-6) {
            entry.rgb = clamp(integral.rgb / integral.a, 0.0, 1.0);
        }
    }
    imageStore(table_image, texel, entry);
}
