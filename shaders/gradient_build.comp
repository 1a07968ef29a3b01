// Builds the gradient texture of include/gradient.glsl once per volume: at every voxel, half the
// difference of its two neighbours along each axis in normalised values (the volume's edge voxels
// repeated beyond it, as the clamped sampler of the central differences sees them).
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(binding = 0) uniform sampler3D volume_texture;
layout(binding = 0, rgba16f) uniform writeonly image3D gradients;
layout(location = 0) uniform vec2 value_map;  // normalised value = texel * x + y

float value_at(ivec3 voxel, ivec3 dims) {
    return texelFetch(volume_texture, clamp(voxel, ivec3(0), dims - 1), 0).r * value_map.x +
           value_map.y;
}

void main() {
    ivec3 dims = textureSize(volume_texture, 0);
    ivec3 voxel = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(voxel, dims))) return;
    vec3 difference = vec3(value_at(voxel + ivec3(1, 0, 0), dims) - value_at(voxel - ivec3(1, 0, 0), dims),
                           value_at(voxel + ivec3(0, 1, 0), dims) - value_at(voxel - ivec3(0, 1, 0), dims),
                           value_at(voxel + ivec3(0, 0, 1), dims) - value_at(voxel - ivec3(0, 0, 1), dims));
    imageStore(gradients, voxel, vec4(0.5 * difference, 0.0));
}
