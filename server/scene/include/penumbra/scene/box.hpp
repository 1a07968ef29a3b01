#pragma once

#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace penumbra::scene {

// Where the volume sits in world space: the unit cube scaled by the volume's physical extent,
// normalised so the longest side is 1, centred on the origin. Anisotropic volumes keep their shape.
struct Box {
    glm::dvec3 min{-0.5};
    glm::dvec3 max{0.5};

    [[nodiscard]] glm::dvec3 size() const { return max - min; }
};

[[nodiscard]] inline Box box_for_extent(glm::dvec3 physical_extent) {
    const double longest = glm::max(physical_extent.x, glm::max(physical_extent.y, physical_extent.z));
    const glm::dvec3 half = longest > 0.0 ? 0.5 * physical_extent / longest : glm::dvec3(0.5);
    return Box{-half, half};
}

}  // namespace penumbra::scene
