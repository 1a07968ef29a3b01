#include "penumbra/scene/camera.hpp"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace penumbra::scene {
namespace {

struct ViewPose {
    View view;
    glm::dvec3 side;  // from the target toward the eye (RAS)
    glm::dvec3 up;
};

constexpr std::array<ViewPose, 6> view_poses{{
        {View::anterior, {0, 1, 0}, {0, 0, 1}},
        {View::posterior, {0, -1, 0}, {0, 0, 1}},
        {View::left, {-1, 0, 0}, {0, 0, 1}},
        {View::right, {1, 0, 0}, {0, 0, 1}},
        {View::superior, {0, 0, 1}, {0, 1, 0}},
        {View::inferior, {0, 0, -1}, {0, 1, 0}},
}};

// A view without a pose, or poses out of View's order, do not compile.
static_assert(view_poses.size() == kViewNames.size());
static_assert([] {
    for (std::size_t i = 0; i < view_poses.size(); ++i) {
        if (view_poses[i].view != static_cast<View>(i)) {
            return false;
        }
    }
    return true;
}());

const ViewPose& pose_of(View view) {
    return view_poses[static_cast<std::size_t>(view)];
}

}  // namespace

CameraFrame camera_frame(const Camera& camera, double aspect) {
    const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
    glm::dvec3 right = glm::cross(forward, camera.up);
    if (glm::length(right) < 1e-12) {
        // Looking along `up`: any perpendicular keeps the frame valid.
        right = glm::cross(forward,
                           std::abs(forward.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0));
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
    const double elevation =
            std::clamp(elevation_degrees, -max_orbit_elevation, max_orbit_elevation);
    Camera camera;
    camera.target = target;
    camera.eye = target + distance * direction_from_angles(azimuth_degrees, elevation);
    camera.up = glm::dvec3(0.0, 0.0, 1.0);
    return camera;
}

Camera view_camera(View view, double distance, glm::dvec3 target, double fov_y_degrees) {
    const ViewPose& pose = pose_of(view);
    Camera camera;
    camera.target = target;
    camera.eye = target + distance * pose.side;
    camera.up = pose.up;
    camera.fov_y_degrees = fov_y_degrees;
    return camera;
}

}  // namespace penumbra::scene
