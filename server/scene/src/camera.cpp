#include "penumbra/scene/camera.hpp"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>

namespace penumbra::scene {

CameraFrame camera_frame(const Camera& camera, double aspect) {
    const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
    glm::dvec3 right = glm::cross(forward, camera.up);
    if (glm::length(right) < 1e-12) {
        // Looking along `up`: any perpendicular keeps the frame valid.
        right = glm::cross(forward, std::abs(forward.x) < 0.9 ? glm::dvec3(1, 0, 0)
                                                              : glm::dvec3(0, 1, 0));
    }
    right = glm::normalize(right);
    const glm::dvec3 up = glm::cross(right, forward);
    const double half_height = std::tan(glm::radians(camera.fov_y_degrees) * 0.5);
    return CameraFrame{camera.eye, forward, right * half_height * aspect, up * half_height};
}

glm::dvec3 direction_from_angles(double azimuth_degrees, double elevation_degrees) {
    const double azimuth = glm::radians(azimuth_degrees);
    const double elevation = glm::radians(elevation_degrees);
    return {std::cos(elevation) * std::sin(azimuth), std::cos(elevation) * std::cos(azimuth),
            std::sin(elevation)};
}

Camera orbit_camera(double azimuth_degrees, double elevation_degrees, double distance,
                    glm::dvec3 target) {
    const double elevation = std::clamp(elevation_degrees, -89.9, 89.9);
    Camera camera;
    camera.target = target;
    camera.eye = target + distance * direction_from_angles(azimuth_degrees, elevation);
    camera.up = glm::dvec3(0.0, 0.0, 1.0);
    return camera;
}

}  // namespace penumbra::scene
