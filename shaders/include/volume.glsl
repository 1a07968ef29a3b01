// Volume sampling in world space; the box maps to texture coordinates [0,1]^3.
layout(binding = 0) uniform sampler3D volume_texture;

vec3 texture_coordinate(vec3 world) {
    return (world - u.box_min.xyz) / (u.box_max.xyz - u.box_min.xyz);
}

// The voxel value mapped so that the volume's range becomes [0, 1].
float sample_value(vec3 world) {
    return texture(volume_texture, texture_coordinate(world)).r * u.value_map.x + u.value_map.y;
}

// Central differences one voxel apart, in normalised value per world unit.
vec3 value_gradient(vec3 world) {
    vec3 h = u.voxel_size.xyz;
    return vec3(sample_value(world + vec3(h.x, 0, 0)) - sample_value(world - vec3(h.x, 0, 0)),
                sample_value(world + vec3(0, h.y, 0)) - sample_value(world - vec3(0, h.y, 0)),
                sample_value(world + vec3(0, 0, h.z)) - sample_value(world - vec3(0, 0, h.z))) /
           (2.0 * h);
}
