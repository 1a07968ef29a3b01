// Volume sampling in world space. In box space (world_to_box) the box is axis-aligned with its
// axes along the volume's index axes, and maps to texture coordinates [0,1]^3.
layout(binding = 0) uniform sampler3D volume_texture;

vec3 box_coordinate(vec3 world) {
    return mat3(u.world_to_box) * world;
}

vec3 texture_coordinate(vec3 world) {
    return (box_coordinate(world) - u.box_min.xyz) / (u.box_max.xyz - u.box_min.xyz);
}

// The nearest point of the box (world space): fragments of a slice polygon that rasterisation
// puts a rounding error outside still count as inside.
vec3 clamp_to_box(vec3 world) {
    return mat3(u.box_to_world) * clamp(box_coordinate(world), u.box_min.xyz, u.box_max.xyz);
}

// RECONSTRUCTION (SETTINGS_RECONSTRUCTION_*): how values between voxels are reconstructed. The
// trilinear filter is the texture unit's; the tricubic B-spline takes 8 linear fetches per value.
#ifndef RECONSTRUCTION
#define RECONSTRUCTION SETTINGS_RECONSTRUCTION_TRILINEAR
#endif

#if RECONSTRUCTION == SETTINGS_RECONSTRUCTION_TRICUBIC
// The cubic B-spline by Sigg & Hadwiger's fetches (GPU Gems 2, ch. 20): along each axis the four
// weights w0..w3 of the voxels i-1..i+2 around a point are two pairs of one sign, so each pair is
// one linear fetch between its two voxels; 2^3 fetches make the 64-voxel sum. Clamp to edge
// repeats the border voxel for i-1 = -1 and i+2 = N, as the 64-voxel sum with clamped indices.

// The two fetches of one axis: their weights and texture coordinates.
struct BsplineFetches {
    vec3 weight0;
    vec3 weight1;
    vec3 coordinate0;
    vec3 coordinate1;
};

// Pairs w0 + w1 at voxels i-1, i and w2 + w3 at i+1, i+2 (each axis), `i` the voxel index below
// the point; texel centres are at (index + 0.5) / size.
BsplineFetches bspline_pairs(vec3 i, vec3 w0, vec3 w1, vec3 w2, vec3 w3, vec3 size) {
    BsplineFetches f;
    f.weight0 = w0 + w1;
    f.weight1 = w2 + w3;
    f.coordinate0 = (i - 0.5 + w1 / f.weight0) / size;
    f.coordinate1 = (i + 1.5 + w3 / f.weight1) / size;
    return f;
}

// The 8 fetches of the weights' outer product, in the volume's normalised units scaled by
// u.value_map.x (without its offset: the derivative weights sum to zero).
float bspline_sum(BsplineFetches f) {
    float sum = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
        bvec3 upper = bvec3((corner & 1) != 0, (corner & 2) != 0, (corner & 4) != 0);
        vec3 weight = mix(f.weight0, f.weight1, upper);
        sum += weight.x * weight.y * weight.z *
               texture(volume_texture, mix(f.coordinate0, f.coordinate1, upper)).r;
    }
    return sum * u.value_map.x;
}

// The point in voxel index space (voxel i's centre at i): the voxel below, and the fraction.
vec3 bspline_index(vec3 world, vec3 size, out vec3 fraction) {
    vec3 x = texture_coordinate(world) * size - 0.5;
    vec3 i = floor(x);
    fraction = x - i;
    return i;
}

BsplineFetches bspline_value_fetches(vec3 i, vec3 f, vec3 size) {
    vec3 g = 1.0 - f;
    vec3 f2 = f * f;
    return bspline_pairs(i, g * g * g / 6.0, (3.0 * f2 * f - 6.0 * f2 + 4.0) / 6.0,
                         (-3.0 * f2 * f + 3.0 * f2 + 3.0 * f + 1.0) / 6.0, f2 * f / 6.0, size);
}

// The derivative's weights, per voxel step: -(1-f)^2/2, (3f^2-4f)/2 (both <= 0), (1+3f)(1-f)/2,
// f^2/2 (both >= 0), so each pair is one fetch again.
BsplineFetches bspline_derivative_fetches(vec3 i, vec3 f, vec3 size) {
    vec3 g = 1.0 - f;
    return bspline_pairs(i, -0.5 * g * g, 0.5 * f * (3.0 * f - 4.0), 0.5 * (1.0 + 3.0 * f) * g,
                         0.5 * f * f, size);
}

float sample_value(vec3 world) {
    vec3 size = vec3(textureSize(volume_texture, 0));
    vec3 f;
    vec3 i = bspline_index(world, size, f);
    return bspline_sum(bspline_value_fetches(i, f, size)) + u.value_map.y;
}

// The B-spline's exact gradient: along each axis the derivative's fetches, the value's fetches
// along the other two (3 x 8 fetches), per voxel step made per world unit and turned from box
// space into world space.
vec3 value_gradient(vec3 world) {
    vec3 size = vec3(textureSize(volume_texture, 0));
    vec3 f;
    vec3 i = bspline_index(world, size, f);
    BsplineFetches value = bspline_value_fetches(i, f, size);
    BsplineFetches derivative = bspline_derivative_fetches(i, f, size);
    vec3 steps;
    for (int axis = 0; axis < 3; ++axis) {
        BsplineFetches along = value;
        along.weight0[axis] = derivative.weight0[axis];
        along.weight1[axis] = derivative.weight1[axis];
        along.coordinate0[axis] = derivative.coordinate0[axis];
        along.coordinate1[axis] = derivative.coordinate1[axis];
        steps[axis] = bspline_sum(along);
    }
    return mat3(u.box_to_world) * (steps / u.voxel_size.xyz);
}
#else
// The voxel value mapped so that the volume's range becomes [0, 1].
float sample_value(vec3 world) {
    return texture(volume_texture, texture_coordinate(world)).r * u.value_map.x + u.value_map.y;
}

// Central differences one voxel apart along the volume's axes, in normalised value per world
// unit, turned from box space into world space (the axes are orthonormal).
vec3 value_gradient(vec3 world) {
    vec3 h = u.voxel_size.xyz;
    mat3 axes = mat3(u.box_to_world);
    vec3 dx = h.x * axes[0];
    vec3 dy = h.y * axes[1];
    vec3 dz = h.z * axes[2];
    return axes * (vec3(sample_value(world + dx) - sample_value(world - dx),
                        sample_value(world + dy) - sample_value(world - dy),
                        sample_value(world + dz) - sample_value(world - dz)) /
                   (2.0 * h));
}
#endif
