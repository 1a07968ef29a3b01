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
