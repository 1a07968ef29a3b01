#pragma once

#include <penumbra/scene/enum_names.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <span>

namespace penumbra::scene {

enum class LightType { directional, point };

inline constexpr std::array<EnumName<LightType>, 2> kLightTypeNames{{
        {LightType::directional, "directional"},
        {LightType::point, "point"},
}};
static_assert(names_each_value(kLightTypeNames));

constexpr std::span<const EnumName<LightType>> names_of(LightType) {
    return kLightTypeNames;
}

struct Light {
    LightType type = LightType::directional;
    glm::dvec3 direction{0.0, 0.0, 1.0};  // toward the light (directional)
    glm::dvec3 position{0.0, 0.0, 3.0};   // world position (point)
    glm::dvec3 color{1.0};
    double intensity = 1.0;
    double ambient = 0.25;  // fraction of the light colour that reaches every sample unshadowed

    bool operator==(const Light&) const = default;
};

// Blinn–Phong material applied when a mode shades with gradients.
struct Shading {
    double diffuse = 0.75;
    double specular = 0.3;
    double shininess = 32.0;

    bool operator==(const Shading&) const = default;
};

}  // namespace penumbra::scene
