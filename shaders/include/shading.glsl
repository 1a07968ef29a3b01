// Blinn–Phong; mirrors server/optics/include/penumbra/optics/shading.hpp.
// POINT_LIGHT (0|1): light_vector is a position rather than a direction.

const float min_gradient_per_voxel = 1e-3;

vec3 direction_to_light(vec3 world) {
#if POINT_LIGHT
    return normalize(u.light_vector.xyz - world);
#else
    return normalize(u.light_vector.xyz);
#endif
}

// The unit normal from a gradient in value per world unit, or zero where the gradient is too
// small to define one (compared per voxel along the volume's axes so the threshold does not
// depend on the volume size).
vec3 normal_from_gradient(vec3 gradient) {
    vec3 per_voxel = (mat3(u.world_to_box) * gradient) * u.voxel_size.xyz;
    if (length(per_voxel) < min_gradient_per_voxel) return vec3(0.0);
    return -normalize(gradient);
}

// x: diffuse term, y: specular term.
vec2 blinn_phong(vec3 normal, vec3 to_light, vec3 to_eye) {
    if (dot(normal, normal) == 0.0) return vec2(1.0, 0.0);
    if (dot(normal, to_eye) < 0.0) normal = -normal;
    vec3 sum = to_light + to_eye;
    float diffuse = max(dot(normal, to_light), 0.0);
    // Light exactly opposite the eye has no half vector (normalize(0) is undefined in GLSL).
    if (dot(sum, sum) < 1e-12) return vec2(diffuse, 0.0);
    vec3 half_vector = sum / length(sum);
    return vec2(diffuse, pow(max(dot(normal, half_vector), 0.0), settings.shading_shininess));
}

// `light` is the fraction of the light that reaches the sample (1 without shadows); ambient light
// is unshadowed.
vec3 shade(vec3 tf_color, vec2 terms, float light) {
    vec3 radiance = u.light_radiance.rgb;
    return tf_color * radiance *
                   (settings.light_ambient + settings.shading_diffuse * terms.x * light) +
           radiance * settings.shading_specular * terms.y * light;
}
