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
    const char* name;
    glm::dvec3 side;  // from the target toward the eye (RAS)
    glm::dvec3 up;
};

constexpr std::array<ViewPose, 6> view_poses{{
        {View::anterior, "anterior", {0, 1, 0}, {0, 0, 1}},
        {View::posterior, "posterior", {0, -1, 0}, {0, 0, 1}},
        {View::left, "left", {-1, 0, 0}, {0, 0, 1}},
        {View::right, "right", {1, 0, 0}, {0, 0, 1}},
        {View::superior, "superior", {0, 0, 1}, {0, 1, 0}},
        {View::inferior, "inferior", {0, 0, -1}, {0, 1, 0}},
}};

const ViewPose& pose_of(View view) {
    return *std::find_if(view_poses.begin(), view_poses.end(),
                         [view](const ViewPose& pose) { return pose.view == view; });
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
    const double elevation = std::clamp(elevation_degrees, -89.9, 89.9);
    Camera camera;
    camera.target = target;
    camera.eye = target + distance * direction_from_angles(azimuth_degrees, elevation);
    camera.up = glm::dvec3(0.0, 0.0, 1.0);
    return camera;
}

const char* to_string(View view) {
    return pose_of(view).name;
}

std::optional<View> parse_view(std::string_view text) {
    for (const ViewPose& pose : view_poses) {
        if (text == pose.name) {
            return pose.view;
        }
    }
    return std::nullopt;
}

std::string view_names() {
    std::string names;
    for (const ViewPose& pose : view_poses) {
        names += std::string(names.empty() ? "" : ", ") + pose.name;
    }
    return names;
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
