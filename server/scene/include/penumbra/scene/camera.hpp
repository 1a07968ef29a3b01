#pragma once

#include <glm/vec3.hpp>

namespace penumbra::scene {

// A perspective pinhole camera in world space. The volume box is centred on the origin and its
// longest side has length 1 (see box.hpp), so distances are in units of that side.
// World space is z-up: volumes are stored with z as the slice axis, which for medical data (RAS
// or LPS) points to the head's top.
struct Camera {
    glm::dvec3 eye{0.0, 2.5, 0.0};
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

// A camera on a sphere around `target`: azimuth about +z, measured from +y toward +x, elevation
// above the xy plane, both in degrees. Elevation is kept within ±89.9° so `up` (+z) stays defined.
// Azimuth 0 looks at a RAS head's face (+y is anterior).
[[nodiscard]] Camera orbit_camera(double azimuth_degrees, double elevation_degrees,
                                  double distance, glm::dvec3 target = glm::dvec3(0.0));

// The unit vector with that azimuth and elevation (same convention as orbit_camera).
[[nodiscard]] glm::dvec3 direction_from_angles(double azimuth_degrees, double elevation_degrees);

}  // namespace penumbra::scene
