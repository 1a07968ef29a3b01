// Empty-space skipping: a coarse grid of bricks over the volume, each marked occupied when the
// transfer function makes any value its samples can read visible (brick_classify.comp). Brick
// (i, j, k) covers texture coordinates [i, i + 1) / G x ... for a grid of G bricks per axis; its
// value range includes the one-voxel border that trilinear samples near its faces read, so a
// sample in an empty brick always classifies as fully transparent and can be left out exactly.
// EMPTY_SPACE_SKIPPING (0|1): 0 samples everything, as before bricks existed.
#ifndef EMPTY_SPACE_SKIPPING
#define EMPTY_SPACE_SKIPPING 0
#endif

#if EMPTY_SPACE_SKIPPING
layout(binding = 3) uniform usampler3D brick_occupancy;

ivec3 brick_of(vec3 world) {
    ivec3 grid = textureSize(brick_occupancy, 0);
    ivec3 brick = ivec3(floor(texture_coordinate(world) * vec3(grid)));
    return clamp(brick, ivec3(0), grid - 1);
}

bool brick_occupied(ivec3 brick) {
    return texelFetch(brick_occupancy, brick, 0).r != 0u;
}

// How far `direction` (unit or not: the result is in its units) goes from `world` before it
// leaves `brick`. Measured in box space, where the bricks are axis-aligned; the box's axes are
// orthonormal, so distances are the same as in world space.
float distance_out_of_brick(vec3 world, vec3 direction, ivec3 brick) {
    vec3 position = box_coordinate(world);
    vec3 along = mat3(u.world_to_box) * direction;
    vec3 grid = vec3(textureSize(brick_occupancy, 0));
    vec3 size = u.box_max.xyz - u.box_min.xyz;
    vec3 lower = u.box_min.xyz + vec3(brick) / grid * size;
    vec3 upper = u.box_min.xyz + vec3(brick + 1) / grid * size;
    vec3 face = mix(lower, upper, greaterThan(along, vec3(0.0)));
    float t = 3.0e38;
    for (int axis = 0; axis < 3; ++axis) {
        if (along[axis] != 0.0) t = min(t, (face[axis] - position[axis]) / along[axis]);
    }
    return max(t, 0.0);
}

// The distance along `direction` from `world` to the end of the empty brick it lies in, or 0
// where that brick is occupied.
float empty_run(vec3 world, vec3 direction) {
    ivec3 brick = brick_of(world);
    return brick_occupied(brick) ? 0.0 : distance_out_of_brick(world, direction, brick);
}

// For a march with samples at t = start + (i + 0.5) * step: the first sample index after `index`
// that the empty brick holding sample `index` does not contain, or `index` itself where that
// brick is occupied. Never less than index + 1 when it leaps, so a march always advances.
int next_sample_outside_empty(vec3 world, vec3 direction, int index, float step) {
    float run = empty_run(world, direction);
    if (run <= 0.0) return index;
    return max(index + 1, index + int(ceil(run / step)));
}
#endif
