#pragma once

#include <penumbra/scene/enum_names.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace penumbra::scene {

// How far the default camera and the named views stand from the target, in box units.
inline constexpr double default_camera_distance = 2.6;

// A perspective pinhole camera in world space. The volume box is centred on the origin and its
// longest side has length 1 (see box.hpp), so distances are in units of that side.
// World space is patient space, RAS and z-up (+x the patient's right, +y anterior, +z superior):
// the renderer turns each volume by its orientation into it. The default camera is the anterior
// view: it looks at the face with superior up.
struct Camera {
    glm::dvec3 eye{0.0, default_camera_distance, 0.0};
    glm::dvec3 target{0.0};
    glm::dvec3 up{0.0, 0.0, 1.0};
    double fov_y_degrees = 30.0;

    bool operator==(const Camera&) const = default;
};

// The camera's orthonormal frame. `right` and `up` are scaled by the half-extent of the image
// plane at distance 1, so pixel rays are `forward + ndc.x * right + ndc.y * up`.
struct CameraFrame {
    glm::dvec3 eye;
    glm::dvec3 forward;
    glm::dvec3 right;
    glm::dvec3 up;
};

[[nodiscard]] CameraFrame camera_frame(const Camera& camera, double aspect);

// How far from the horizon an orbit's eye goes, in degrees: short of the poles, so that `up` (+z)
// stays defined.
inline constexpr double max_orbit_elevation = 89.9;

// A camera on a sphere around `target`: azimuth about +z, measured from +y toward +x, elevation
// above the xy plane, both in degrees. Elevation is kept within ±max_orbit_elevation.
// Azimuth 0 looks at a RAS head's face (+y is anterior).
[[nodiscard]] Camera orbit_camera(double azimuth_degrees, double elevation_degrees, double distance,
                                  glm::dvec3 target = glm::dvec3(0.0));

// The unit vector with that azimuth and elevation (same convention as orbit_camera).
[[nodiscard]] glm::dvec3 direction_from_angles(double azimuth_degrees, double elevation_degrees);

// The views named by anatomy, as radiologists and Slicer name them: the view from that side of the
// patient. Horizontal views keep superior up; the superior and inferior views put anterior up.
enum class View { anterior, posterior, left, right, superior, inferior };

inline constexpr std::array<EnumName<View>, 6> kViewNames{{
        {View::anterior, "anterior"},
        {View::posterior, "posterior"},
        {View::left, "left"},
        {View::right, "right"},
        {View::superior, "superior"},
        {View::inferior, "inferior"},
}};
static_assert(names_each_value(kViewNames));

constexpr std::span<const EnumName<View>> names_of(View) {
    return kViewNames;
}

// The camera that sees `target` from that side at `distance`, keeping `fov_y_degrees`.
[[nodiscard]] Camera view_camera(View view, double distance = default_camera_distance,
                                 glm::dvec3 target = glm::dvec3(0.0), double fov_y_degrees = 30.0);

}  // namespace penumbra::scene
