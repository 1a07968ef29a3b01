// Classifies the brick grid of empty-space skipping (include/empty_space.glsl) against the
// transfer function, on the GPU whenever the TF changes: the bricks' value ranges stay uploaded,
// so a TF drag costs this pass and nothing else.
//   STEP 0 (one invocation): visible_before[i] = how many of the TF table's first i entries have
//          any opacity.
//   STEP 1 (one invocation per brick): occupied when any table entry that linear filtering reads
//          for a value in the brick's range is visible and, where a label map is drawn (LABELS 1),
//          any label the brick's samples can take is shown; a brick of a single label says which
//          (2 + its index), so that its samples need not fetch it.
#include "include/transfer_function.glsl"

#ifndef LABELS
#define LABELS 0
#endif
#if LABELS
#include "include/label_styles.glsl"
// Brick b's label indices (render::BrickLabels) are brick_labels[brick_label_starts[b] ..
// brick_label_starts[b + 1]).
layout(std430, binding = 1) readonly buffer BrickLabelStarts {
    uint brick_label_starts[];
};
layout(std430, binding = 2) readonly buffer BrickLabelIndices {
    uint brick_labels[];
};
#endif

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(binding = 4) uniform sampler3D brick_ranges;  // rg: min, max of the normalised values
layout(binding = 0, r16ui) uniform writeonly uimage3D brick_occupancy_image;
layout(std430, binding = 0) buffer VisibleEntries {
    uint visible_before[];
};
layout(location = 0) uniform int step;

void main() {
    int entries = textureSize(transfer_function_texture, 0);
    if (step == 0) {
        if (gl_GlobalInvocationID != uvec3(0)) return;
        uint count = 0u;
        visible_before[0] = 0u;
        for (int i = 0; i < entries; ++i) {
            if (texelFetch(transfer_function_texture, i, 0).a > 0.0) ++count;
            visible_before[i + 1] = count;
        }
        return;
    }
    ivec3 brick = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(brick, textureSize(brick_ranges, 0)))) return;
    vec2 range = clamp(texelFetch(brick_ranges, brick, 0).rg, 0.0, 1.0);
    // A value v reads entries floor(v * N - 0.5) and the one above; one more either side covers
    // the rounding of the texture unit's filtering.
    int lowest = clamp(int(floor(range.x * float(entries) - 0.5)) - 1, 0, entries - 1);
    int highest = clamp(int(floor(range.y * float(entries) - 0.5)) + 2, 0, entries - 1);
    bool occupied = visible_before[highest + 1] > visible_before[lowest];
    uint occupancy = occupied ? 1u : 0u;
#if LABELS
    ivec3 grid = textureSize(brick_ranges, 0);
    uint b = uint(brick.x + grid.x * (brick.y + grid.y * brick.z));
    uint first = brick_label_starts[b];
    uint end = brick_label_starts[b + 1u];
    bool shown = false;
    for (uint k = first; k < end && occupied; ++k) {
        shown = shown || label_style(int(brick_labels[k])).a > 0.0;
    }
    occupancy = !(occupied && shown) ? 0u : end - first == 1u ? 2u + brick_labels[first] : 1u;
#endif
    imageStore(brick_occupancy_image, brick, uvec4(occupancy));
}
