#pragma once

#include <penumbra/base/result.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace penumbra::scene {

// Where the volume sits in world space (RAS: +x right, +y anterior, +z superior). In box space
// the volume is the unit cube scaled by its physical extent, normalised so the longest side is 1
// and centred on the origin (anisotropic volumes keep their shape); box axis x runs along the
// volume's index i, y along j, z along k. `axes` turns box space into world space: its columns
// are the world directions of the index axes (the volume's orientation, a rotation possibly with a
// reflection), so the box stays centred on the world origin and anatomy lies where it belongs
// however the file stores it.
struct Box {
    glm::dvec3 min{-0.5};
    glm::dvec3 max{0.5};
    glm::dmat3 axes{1.0};          // box -> world
    glm::dmat3 inverse_axes{1.0};  // world -> box

    [[nodiscard]] glm::dvec3 size() const { return max - min; }

    [[nodiscard]] glm::dvec3 to_box(glm::dvec3 world) const { return inverse_axes * world; }

    [[nodiscard]] glm::dvec3 to_world(glm::dvec3 box_point) const { return axes * box_point; }

    [[nodiscard]] glm::dvec3 centre() const { return to_world(0.5 * (min + max)); }

    [[nodiscard]] bool contains(glm::dvec3 world) const {
        const glm::dvec3 p = to_box(world);
        return p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y && p.z >= min.z &&
               p.z <= max.z;
    }
};

// The box of a volume with that physical extent (dims x spacing) whose index axes point along
// the columns of `axes` in world space.
[[nodiscard]] inline Box box_for_extent(glm::dvec3 physical_extent,
                                        const glm::dmat3& axes = glm::dmat3(1.0)) {
    const double longest =
            glm::max(physical_extent.x, glm::max(physical_extent.y, physical_extent.z));
    const glm::dvec3 half = longest > 0.0 ? 0.5 * physical_extent / longest : glm::dvec3(0.5);
    return Box{-half, half, axes, glm::inverse(axes)};
}

// Where patient space (RAS millimetres) lies in world space: world = (patient - centre) /
// millimetres_per_unit. World space is patient space moved so that the volume's box is centred on
// the origin and scaled so that its longest side is 1; no rotation, both being RAS.
struct PatientPlacement {
    glm::dvec3 centre{0.0};
    double millimetres_per_unit = 1.0;

    [[nodiscard]] glm::dvec3 to_world(glm::dvec3 patient) const {
        return (patient - centre) / millimetres_per_unit;
    }

    [[nodiscard]] glm::dvec3 to_patient(glm::dvec3 world) const {
        return centre + world * millimetres_per_unit;
    }
};

// The placement of a volume of `dims` voxels `spacing` apart whose voxel (0, 0, 0) is centred at
// patient point `origin` and whose index axes point along the columns of `axes`, drawn in the box
// box_for_extent(dims * spacing, axes) gives it: the box spans the voxels' outer faces, so its
// centre is the centre of the middle voxel.
[[nodiscard]] inline PatientPlacement patient_placement(glm::dvec3 origin, const glm::dmat3& axes,
                                                        glm::dvec3 spacing, glm::dvec3 dims) {
    const glm::dvec3 extent = dims * spacing;
    const double longest = glm::max(extent.x, glm::max(extent.y, extent.z));
    return PatientPlacement{origin + axes * (0.5 * (extent - spacing)),
                            longest > 0.0 ? longest : 1.0};
}

// The oriented box needs a rotation, possibly with a reflection (orthonormal columns): rays, slice
// polygons and gradients turn between box and world space by it. A sheared transform (a CT
// gantry tilt) must be resampled onto an orthogonal grid before it can be drawn.
[[nodiscard]] inline base::Status check_axes(const glm::dmat3& axes) {
    constexpr double tolerance = 1e-4;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            const double expected = i == j ? 1.0 : 0.0;
            if (!(std::abs(glm::dot(axes[i], axes[j]) - expected) <= tolerance)) {
                return base::make_error(base::ErrorCode::unsupported_orientation,
                                        "the volume's axes are not orthonormal (a sheared or "
                                        "scaled transform, such as a gantry tilt); it must be "
                                        "resampled onto an orthogonal grid to be drawn",
                                        "axes");
            }
        }
    }
    return base::Ok{};
}

}  // namespace penumbra::scene
