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

// 0: empty; 1: occupied; 2 + i: occupied, and every sample in it takes label index i (LABELS).
uint brick_occupancy_of(ivec3 brick) {
    return texelFetch(brick_occupancy, brick, 0).r;
}

bool brick_occupied(ivec3 brick) {
    return brick_occupancy_of(brick) != 0u;
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

// A walk through the brick grid along the line origin + t * direction (Amanatides and Woo), for
// a march that asks about consecutive stretches of one line: each brick the line crosses is
// looked up once, however many stretches lie in it. Bricks outside the grid count as empty: no
// sample is taken there. Written with whole-vector operations: a vector indexed by a loop counter
// costs a software rasteriser a scalar loop per access.
struct BrickWalk {
    vec3 grid_origin;  // the line's origin in brick units (brick i spans [i, i + 1))
    vec3 t_per_brick;  // 1 / |direction| per axis in brick units; 0 where the line is parallel
    ivec3 step;        // -1, 0 or +1 per axis
    ivec3 grid;        // bricks per axis
    ivec3 brick;       // the brick the walk stands in
    vec3 exits;        // the t at which the line crosses the brick's next face on each axis
    float entry;       // the t at which the line enters the brick
    float exit;        // and leaves it
    bool empty;
};

// Each crossing from the origin rather than summed step by step, so that rounding does not build
// up along the walk.
void enter_brick(inout BrickWalk walk, ivec3 brick, float entry) {
    walk.brick = brick;
    walk.entry = entry;
    vec3 face = vec3(brick + max(walk.step, ivec3(0)));
    walk.exits = mix((face - walk.grid_origin) * vec3(walk.step) * walk.t_per_brick,
                     vec3(3.0e38), equal(walk.step, ivec3(0)));
    walk.exit = min(walk.exits.x, min(walk.exits.y, walk.exits.z));
    bool outside = any(lessThan(brick, ivec3(0))) || any(greaterThanEqual(brick, walk.grid));
    walk.empty = outside || !brick_occupied(brick);
}

// Starts at the brick holding the point at `t`, clamped into the grid: the line's entry into the
// box may round to just outside it.
BrickWalk start_brick_walk(vec3 origin, vec3 direction, float t) {
    BrickWalk walk;
    walk.grid = textureSize(brick_occupancy, 0);
    vec3 grid = vec3(walk.grid);
    walk.grid_origin = texture_coordinate(origin) * grid;
    vec3 along = mat3(u.world_to_box) * direction / (u.box_max.xyz - u.box_min.xyz) * grid;
    walk.step = ivec3(sign(along));
    walk.t_per_brick = mix(1.0 / abs(along), vec3(0.0), equal(along, vec3(0.0)));
    ivec3 brick = clamp(ivec3(floor(walk.grid_origin + t * along)), ivec3(0), walk.grid - 1);
    enter_brick(walk, brick, t);
    return walk;
}

// Steps into the next brick, across the face where the line leaves the current one.
void advance_brick_walk(inout BrickWalk walk) {
    bvec3 leaves = equal(walk.exits, vec3(walk.exit));
    // One axis only where the line leaves through an edge or a corner: x before y before z.
    ivec3 across = ivec3(leaves.x, leaves.y && !leaves.x, leaves.z && !leaves.x && !leaves.y);
    enter_brick(walk, walk.brick + across * walk.step, walk.exit);
}

// The t from which the line may meet something, looking from `start` on: `start` itself where
// its brick is occupied, else where the first occupied brick after it begins, or `limit` where
// none begins before that. Successive calls must not go back along the line.
float occupied_from(inout BrickWalk walk, float start, float limit) {
    while (walk.exit <= start) advance_brick_walk(walk);
    if (!walk.empty) return start;
    while (walk.exit < limit) {
        advance_brick_walk(walk);
        if (!walk.empty) return walk.entry;
    }
    return limit;
}
#endif
