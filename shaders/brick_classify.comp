// Classifies the brick grid of empty-space skipping (include/empty_space.glsl) against the
// transfer function, on the GPU whenever the TF changes: the bricks' value ranges stay uploaded,
// so a TF drag costs this pass and nothing else.
//   STEP 0 (one invocation): visible_before[i] = how many of the TF table's first i entries have
//          any opacity.
//   STEP 1 (one invocation per brick): occupied when any table entry that linear filtering reads
//          for a value in the brick's range is visible.
#include "include/transfer_function.glsl"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(binding = 4) uniform sampler3D brick_ranges;  // rg: min, max of the normalised values
layout(binding = 0, r8ui) uniform writeonly uimage3D brick_occupancy_image;
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
    imageStore(brick_occupancy_image, brick, uvec4(occupied ? 1u : 0u));
}
