// The gradient a shaded sample uses, in normalised value per world unit.
// GRADIENT_TEXTURE (0|1): 1 reads one filtered texel of per-voxel central differences built once
// per volume (gradient_build.comp); 0 takes central differences of six volume samples around the
// sample (volume.glsl), or with tricubic reconstruction the B-spline's derivative (the renderer
// never sets GRADIENT_TEXTURE with it). Central differences and the texture agree at voxel
// centres; the renderer picks the faster per device.
#ifndef GRADIENT_TEXTURE
#define GRADIENT_TEXTURE 0
#endif

#if GRADIENT_TEXTURE
layout(binding = 5) uniform sampler3D gradient_texture;  // rgb: value change per voxel step

vec3 sample_gradient(vec3 world) {
    // Differences along the volume's axes, turned from box space into world space.
    return mat3(u.box_to_world) *
           (texture(gradient_texture, texture_coordinate(world)).rgb / u.voxel_size.xyz);
}
#else
vec3 sample_gradient(vec3 world) {
    return value_gradient(world);
}
#endif
