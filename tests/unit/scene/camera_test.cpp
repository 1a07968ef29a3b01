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

// Each named view from its side of the patient (RAS world): which way the viewer looks, which
// patient direction is up on screen and which is to the right.
TEST(View, LooksFromItsSideWithTheAnatomicalUp) {
    struct Expected {
        View view;
        glm::dvec3 forward;
        glm::dvec3 screen_up;
        glm::dvec3 screen_right;
    };

    const glm::dvec3 r{1, 0, 0};
    const glm::dvec3 a{0, 1, 0};
    const glm::dvec3 s{0, 0, 1};
    // Facing the patient, the patient's left is on the viewer's right.
    for (const Expected& e :
         {Expected{View::anterior, -a, s, -r}, Expected{View::posterior, a, s, r},
          Expected{View::left, r, s, -a}, Expected{View::right, -r, s, a},
          Expected{View::superior, -s, a, r}, Expected{View::inferior, s, a, -r}}) {
        SCOPED_TRACE(to_string(e.view));
        const Camera camera = view_camera(e.view, 3.0, {0.1, 0.2, 0.3});
        EXPECT_NEAR(glm::length(camera.eye - camera.target), 3.0, eps);
        const CameraFrame frame = camera_frame(camera, 1.0);
        EXPECT_NEAR(glm::length(frame.forward - e.forward), 0.0, eps);
        EXPECT_NEAR(glm::length(glm::normalize(frame.up) - e.screen_up), 0.0, eps);
        EXPECT_NEAR(glm::length(glm::normalize(frame.right) - e.screen_right), 0.0, eps);
        EXPECT_EQ(parse_name<View>(to_string(e.view)), e.view);
    }
    EXPECT_FALSE(parse_name<View>("front").has_value());
    EXPECT_EQ(name_list<View>(", "), "anterior, posterior, left, right, superior, inferior");
}

// The default camera is the anterior view: it looks at the face with superior up.
TEST(View, TheDefaultCameraIsTheAnteriorView) {
    EXPECT_EQ(Camera{}, view_camera(View::anterior));
    EXPECT_EQ(view_camera(View::anterior, 2.0).eye, orbit_camera(0.0, 0.0, 2.0).eye);
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
