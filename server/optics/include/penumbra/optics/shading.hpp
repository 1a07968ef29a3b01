#pragma once

// Blinn–Phong local lighting, shared by the CPU reference and shaders/include/shading.glsl.

#include <penumbra/scene/light.hpp>

#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace penumbra::optics {

// Below this gradient magnitude (normalised value per voxel) a sample has no usable normal and is
// lit as if it faced the light: homogeneous regions must not flicker with noise directions.
inline constexpr double min_gradient_per_voxel = 1e-3;

struct LightTerms {
    double diffuse = 0.0;   // max(N·L, 0), or 1 without a normal
    double specular = 0.0;  // max(N·H, 0)^shininess, or 0 without a normal
};

// `to_light` and `to_eye` are unit vectors from the sample. `normal` is unit length, or zero when
// the gradient was too small. Two-sided: the normal is turned toward the eye.
inline LightTerms blinn_phong(glm::dvec3 normal, glm::dvec3 to_light, glm::dvec3 to_eye,
                              double shininess) {
    if (glm::dot(normal, normal) == 0.0) {
        return {1.0, 0.0};
    }
    if (glm::dot(normal, to_eye) < 0.0) {
        normal = -normal;
    }
    const glm::dvec3 sum = to_light + to_eye;
    const double diffuse = glm::max(glm::dot(normal, to_light), 0.0);
    // Light exactly opposite the eye has no half vector; such a light never shows a highlight.
    if (glm::dot(sum, sum) < 1e-12) {
        return {diffuse, 0.0};
    }
    const glm::dvec3 half_vector = sum / glm::length(sum);
    return {diffuse, glm::pow(glm::max(glm::dot(normal, half_vector), 0.0), shininess)};
}

// The colour a lit sample emits: TF colour × light × (ambient + diffuse × T) + light × specular
// × T, where T (`light_reaching`, 1 without shadows) is the fraction of the direct light that
// arrives; ambient light is unshadowed.
inline glm::dvec3 shade(glm::dvec3 tf_color, const LightTerms& terms, const scene::Light& light,
                        const scene::Shading& shading, double light_reaching = 1.0) {
    const glm::dvec3 radiance = light.color * light.intensity;
    return tf_color * radiance *
                   (light.ambient + shading.diffuse * terms.diffuse * light_reaching) +
           radiance * shading.specular * terms.specular * light_reaching;
}

}  // namespace penumbra::optics
