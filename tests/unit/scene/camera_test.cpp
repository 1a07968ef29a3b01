#include <penumbra/scene/box.hpp>
#include <penumbra/scene/camera.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>

namespace penumbra::scene {
namespace {

constexpr double eps = 1e-12;

TEST(Camera, OrbitAzimuthZeroLooksFromPlusYWithZUp) {
    const Camera camera = orbit_camera(0.0, 0.0, 3.0);
    EXPECT_NEAR(camera.eye.x, 0.0, eps);
    EXPECT_NEAR(camera.eye.y, 3.0, eps);
    EXPECT_NEAR(camera.eye.z, 0.0, eps);
    const CameraFrame frame = camera_frame(camera, 1.0);
    EXPECT_NEAR(frame.forward.y, -1.0, eps);
    EXPECT_GT(frame.up.z, 0.0);
}

TEST(Camera, FrameIsOrthogonalAndScaledByFieldOfView) {
    Camera camera = orbit_camera(37.0, 21.0, 2.0);
    camera.fov_y_degrees = 60.0;
    const CameraFrame frame = camera_frame(camera, 2.0);
    EXPECT_NEAR(glm::length(frame.forward), 1.0, eps);
    EXPECT_NEAR(glm::dot(frame.forward, frame.right), 0.0, eps);
    EXPECT_NEAR(glm::dot(frame.forward, frame.up), 0.0, eps);
    EXPECT_NEAR(glm::dot(frame.right, frame.up), 0.0, eps);
    EXPECT_NEAR(glm::length(frame.up), std::tan(M_PI / 6.0), eps);
    EXPECT_NEAR(glm::length(frame.right), 2.0 * std::tan(M_PI / 6.0), eps);
}

TEST(Camera, LookingAlongUpStillGivesAFrame) {
    Camera camera;
    camera.eye = {0.0, 0.0, 3.0};
    camera.up = {0.0, 0.0, 1.0};
    const CameraFrame frame = camera_frame(camera, 1.0);
    EXPECT_FALSE(std::isnan(frame.right.x));
    EXPECT_GT(glm::length(frame.right), 0.1);
}

TEST(Camera, DirectionFromAnglesIsUnit) {
    for (double az : {-170.0, 0.0, 45.0, 300.0}) {
        for (double el : {-80.0, 0.0, 33.0}) {
            EXPECT_NEAR(glm::length(direction_from_angles(az, el)), 1.0, eps);
        }
    }
    EXPECT_NEAR(direction_from_angles(0.0, 90.0).z, 1.0, eps);
}

TEST(Box, KeepsAspectWithLongestSideOne) {
    const Box box = box_for_extent({181.0, 217.0, 90.5});
    EXPECT_NEAR(box.size().y, 1.0, eps);
    EXPECT_NEAR(box.size().x, 181.0 / 217.0, eps);
    EXPECT_NEAR(box.size().z, 90.5 / 217.0, eps);
    EXPECT_NEAR(box.min.x + box.max.x, 0.0, eps);
}

}  // namespace
}  // namespace penumbra::scene
