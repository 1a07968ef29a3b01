// One declaration of what the C++ side sends each frame; mirrored field for field by
// server/render/src/uniforms.hpp (static_asserts there check the std140 offsets).
layout(std140, binding = 0) uniform FrameUniforms {
    vec4 eye;               // xyz: camera position
    vec4 camera_forward;    // xyz: unit view direction
    vec4 camera_right;      // xyz: right * tan(fov/2) * aspect
    vec4 camera_up;         // xyz: up * tan(fov/2)
    vec4 box_min;           // xyz: volume box corner (world)
    vec4 box_max;           // xyz
    vec4 voxel_size;        // xyz: one voxel's size in world units
    vec4 background;        // rgb
    vec4 light_radiance;    // rgb: light colour * intensity; w: ambient
    vec4 light_vector;      // xyz: direction toward a directional light, or point-light position
    vec4 shading;           // x: diffuse, y: specular, z: shininess
    vec4 value_map;         // x: scale, y: offset: normalised value = texel * scale + offset
    vec4 march;             // x: sample distance, y: opacity unit distance, z: early termination
    ivec4 image_size;       // xy: output size in pixels
} u;
