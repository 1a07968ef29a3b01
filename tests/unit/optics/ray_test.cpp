#include <penumbra/optics/ray.hpp>

#include <gtest/gtest.h>

namespace penumbra::optics {
namespace {

const scene::Box unit_box{glm::dvec3(-0.5), glm::dvec3(0.5)};

TEST(IntersectBox, HitsAlongAnAxis) {
    const BoxHit hit = intersect_box({0.0, 2.0, 0.0}, {0.0, -1.0, 0.0}, unit_box);
    ASSERT_TRUE(hit.hit);
    EXPECT_DOUBLE_EQ(hit.t_near, 1.5);
    EXPECT_DOUBLE_EQ(hit.t_far, 2.5);
}

TEST(IntersectBox, MissesBesideTheBox) {
    EXPECT_FALSE(intersect_box({0.7, 2.0, 0.0}, {0.0, -1.0, 0.0}, unit_box).hit);
}

TEST(IntersectBox, BoxBehindTheOriginIsAMiss) {
    EXPECT_FALSE(intersect_box({0.0, 2.0, 0.0}, {0.0, 1.0, 0.0}, unit_box).hit);
}

TEST(IntersectBox, StartsAtZeroInsideTheBox) {
    const BoxHit hit = intersect_box({0.1, 0.0, 0.0}, {1.0, 0.0, 0.0}, unit_box);
    ASSERT_TRUE(hit.hit);
    EXPECT_DOUBLE_EQ(hit.t_near, 0.0);
    EXPECT_DOUBLE_EQ(hit.t_far, 0.4);
}

TEST(IntersectBox, RayInAFacePlaneParallelToItDoesNotProduceNan) {
    const BoxHit hit = intersect_box({0.5, 2.0, 0.0}, {0.0, -1.0, 0.0}, unit_box);
    EXPECT_FALSE(std::isnan(hit.t_near));
    EXPECT_FALSE(std::isnan(hit.t_far));
}

TEST(IntersectBox, DiagonalThroughCorners) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(1.0));
    const BoxHit hit = intersect_box(glm::dvec3(-1.0), d, unit_box);
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t_far - hit.t_near, std::sqrt(3.0), 1e-12);
}

TEST(PlanMarching, EqualStepsNoLongerThanRequested) {
    const Marching m = plan_marching(1.0, 2.0, 0.3);
    EXPECT_EQ(m.count, 4);
    EXPECT_DOUBLE_EQ(m.step, 0.25);
    EXPECT_EQ(plan_marching(1.0, 1.0, 0.1).count, 0);
    EXPECT_EQ(plan_marching(0.0, 0.001, 0.5).count, 1);
}

TEST(PixelRay, CentrePixelOfOddImageLooksForward) {
    const scene::CameraFrame frame = scene::camera_frame(scene::orbit_camera(10.0, 20.0, 3.0), 1.0);
    const glm::dvec3 d = pixel_ray_direction(frame, 2, 2, 5, 5);
    EXPECT_NEAR(glm::dot(d, frame.forward), 1.0, 1e-12);
    // Row 0 is the top: its rays tilt toward `up`.
    EXPECT_GT(glm::dot(pixel_ray_direction(frame, 2, 0, 5, 5), frame.up), 0.0);
}

}  // namespace
}  // namespace penumbra::optics
