#include <penumbra/optics/ray.hpp>

#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

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

// A box turned 45 degrees about z: a ray along y through the centre enters at the edge between
// two faces, half a diagonal from the centre, where the axis-aligned box would have its face.
TEST(IntersectBox, FollowsTheBoxOrientation) {
    const glm::dmat3 turned(glm::rotate(glm::dmat4(1.0), glm::radians(45.0), {0.0, 0.0, 1.0}));
    const scene::Box box = scene::box_for_extent(glm::dvec3(1.0), turned);
    const BoxHit hit = intersect_box({0.0, 2.0, 0.0}, {0.0, -1.0, 0.0}, box);
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t_near, 2.0 - std::sqrt(0.5), 1e-12);
    EXPECT_NEAR(hit.t_far, 2.0 + std::sqrt(0.5), 1e-12);
    // Beside the axis-aligned box, inside the turned one.
    EXPECT_TRUE(intersect_box({0.6, 2.0, 0.0}, {0.0, -1.0, 0.0}, box).hit);
    EXPECT_FALSE(intersect_box({0.6, 2.0, 0.0}, {0.0, -1.0, 0.0}, unit_box).hit);
}

// A mirrored box (LAS) occupies the same space as the unmirrored one.
TEST(IntersectBox, AReflectionLeavesASymmetricBoxWhereItWas) {
    const scene::Box mirrored =
            scene::box_for_extent({0.8, 1.0, 0.6}, glm::dmat3({-1, 0, 0}, {0, 1, 0}, {0, 0, 1}));
    const scene::Box plain = scene::box_for_extent({0.8, 1.0, 0.6});
    const glm::dvec3 direction = glm::normalize(glm::dvec3(-0.1, -1.0, 0.05));
    const BoxHit a = intersect_box({0.1, 2.0, 0.0}, direction, mirrored);
    const BoxHit b = intersect_box({0.1, 2.0, 0.0}, direction, plain);
    ASSERT_TRUE(a.hit && b.hit);
    EXPECT_NEAR(a.t_near, b.t_near, 1e-12);
    EXPECT_NEAR(a.t_far, b.t_far, 1e-12);
}

TEST(RayStartOffset, MidpointWithoutJitter) {
    EXPECT_EQ(ray_start_offset(false, 7, 3, 0), 0.5);
    EXPECT_EQ(ray_start_offset(false, 7, 3, 5), 0.5);
}

TEST(RayStartOffset, JitteredOffsetsFillTheStepEvenly) {
    // Over a tile of pixels the offsets stay within [0, 1), spread over the whole step (every
    // tenth of it is hit about equally often) and neighbours differ.
    std::array<int, 10> bins{};
    int neighbours_equal = 0;
    for (int y = 0; y < 64; ++y) {
        for (int x = 0; x < 64; ++x) {
            const double offset = ray_start_offset(true, x, y, 0);
            ASSERT_GE(offset, 0.0);
            ASSERT_LT(offset, 1.0);
            ++bins[static_cast<std::size_t>(offset * 10.0)];
            neighbours_equal += std::abs(offset - ray_start_offset(true, x + 1, y, 0)) < 1e-3;
        }
    }
    for (const int count : bins) {
        EXPECT_NEAR(count, 64 * 64 / 10, 64 * 64 / 10 / 4);
    }
    EXPECT_LT(neighbours_equal, 64 * 64 / 100);
}

TEST(RayStartOffset, SuccessiveStepsCoverTheStepOfOnePixel) {
    // Eight refinement steps of one pixel land in eight different eighths-ish of the step: their
    // smallest gap is far from zero (the golden-ratio sequence), so averaging them converges.
    std::vector<double> offsets;
    for (int step = 0; step < 8; ++step) {
        offsets.push_back(ray_start_offset(true, 11, 29, step));
    }
    std::sort(offsets.begin(), offsets.end());
    for (std::size_t i = 1; i < offsets.size(); ++i) {
        EXPECT_GT(offsets[i] - offsets[i - 1], 0.05);
    }
}

}  // namespace
}  // namespace penumbra::optics
