// A turntable's views: the camera and the light turned together about the view's up direction,
// a whole turn in equal steps or a rocking sweep.

#include <penumbra/scene/turntable.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

namespace penumbra::scene {
namespace {

void expect_near(glm::dvec3 actual, glm::dvec3 expected) {
    EXPECT_NEAR(glm::distance(actual, expected), 0.0, 1e-9)
            << "(" << actual.x << ", " << actual.y << ", " << actual.z << ")";
}

TEST(Turntable, TheCameraAndTheLightTurnTogetherAboutTheViewsUp) {
    Camera camera;  // the anterior view: eye on +y, superior (+z) up
    camera.target = {0.1, 0.0, 0.2};
    camera.eye = camera.target + glm::dvec3(0.0, 2.0, 0.0);
    Light light;
    light.direction = {0.0, 1.0, 1.0};
    light.position = camera.target + glm::dvec3(1.0, 0.0, 0.5);
    const TurnedView quarter = turned_view(camera, light, 90.0);
    // A quarter turn about +z takes +y to -x, about the target.
    expect_near(quarter.camera.eye, camera.target + glm::dvec3(-2.0, 0.0, 0.0));
    expect_near(quarter.camera.target, camera.target);
    expect_near(quarter.camera.up, camera.up);
    expect_near(quarter.light.direction, {-1.0, 0.0, 1.0});
    expect_near(quarter.light.position, camera.target + glm::dvec3(0.0, 1.0, 0.5));
    EXPECT_EQ(quarter.camera.fov_y_degrees, camera.fov_y_degrees);
    EXPECT_EQ(quarter.light.intensity, light.intensity);
    // A whole turn comes back; the view seen from the light does not change with the turn.
    expect_near(turned_view(camera, light, 360.0).camera.eye, camera.eye);
    EXPECT_NEAR(
            glm::dot(glm::normalize(quarter.camera.eye - quarter.camera.target),
                     glm::normalize(quarter.light.direction)),
            glm::dot(glm::normalize(camera.eye - camera.target), glm::normalize(light.direction)),
            1e-12);
}

TEST(Turntable, AWholeTurnInEqualStepsOrARockingSweep) {
    EXPECT_EQ(turntable_degrees(0, 8), 0.0);
    EXPECT_EQ(turntable_degrees(1, 8), 45.0);
    EXPECT_EQ(turntable_degrees(7, 8), 315.0) << "one step short of the first: the movie loops";
    EXPECT_NEAR(turntable_degrees(0, 8, 30.0), 0.0, 1e-12);
    EXPECT_NEAR(turntable_degrees(2, 8, 30.0), 30.0, 1e-12);
    EXPECT_NEAR(turntable_degrees(4, 8, 30.0), 0.0, 1e-12);
    EXPECT_NEAR(turntable_degrees(6, 8, 30.0), -30.0, 1e-12);
}

TEST(Turntable, AFrameIsTheRequestWithItsViewTurned) {
    FrameRequest request;
    request.settings.width = 48;
    const FrameRequest third = turntable_frame(request, 2, 8, 0.0);
    const TurnedView view = turned_view(request.camera, request.light, 90.0);
    EXPECT_EQ(third.camera, view.camera);
    EXPECT_EQ(third.light, view.light);
    EXPECT_EQ(third.settings, request.settings) << "only the view turns";
}

}  // namespace
}  // namespace penumbra::scene
