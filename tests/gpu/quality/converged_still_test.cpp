// A still refined as a session refines it (AccuracyBench::converged): it stops where
// scene::refines_after says, its time adds up its steps, and it is closer to the fine-step image
// than the first still.

#include "synthetic_volumes.hpp"

#include <penumbra/quality/sweep.hpp>
#include <penumbra/render/renderer.hpp>

#include <gtest/gtest.h>

#include <memory>

namespace penumbra::quality {
namespace {

class ConvergedStillTest : public ::testing::Test {
protected:
    void SetUp() override {
        auto created = render::Renderer::create();
        ASSERT_TRUE(created.ok()) << created.error().to_string();
        renderer_ = std::move(created.value());
        ASSERT_TRUE(renderer_
                            ->set_volume(std::make_shared<const volume::Volume>(
                                    test::sphere_volume(24, 0.35f)))
                            .ok());
    }

    // A sphere under a steep transfer function at a coarse step: rings a jittered still trades for
    // noise, which its steps average away.
    static scene::FrameRequest still(scene::Mode mode) {
        scene::FrameRequest request;
        request.camera = scene::orbit_camera(30.0, 20.0, 2.4);
        request.transfer_function = {"steep",
                                     {{0.0, {1.0, 0.8, 0.6}}, {1.0, {1.0, 0.8, 0.6}}},
                                     {{0.0, 0.0}, {0.45, 0.0}, {0.55, 0.9}, {1.0, 0.9}}};
        request.settings.mode = mode;
        request.settings.width = 48;
        request.settings.height = 48;
        request.settings.sample_distance = 1.0 / 24.0;
        request.settings.light_buffer.slices = 16;
        request.settings.light_buffer.resolution = 32;
        request.settings.jitter = true;
        return request;
    }

    std::unique_ptr<render::Renderer> renderer_;
};

TEST_F(ConvergedStillTest, WithoutAThresholdRefinesToTheLimitAndAddsUpItsTime) {
    AccuracyBench bench(*renderer_, 1);
    auto converged = bench.converged(still(scene::Mode::dvr), 5, 0.0);
    ASSERT_TRUE(converged.ok()) << converged.error().to_string();
    EXPECT_EQ(converged->steps, 5);
    EXPECT_GT(converged->last.frame_ms, converged->still.frame_ms);
    EXPECT_GT(converged->last_change, 0.0);
    // The still's warm-up and timed frame, then the steps.
    EXPECT_EQ(bench.frames(), 2U + 5U);
}

TEST_F(ConvergedStillTest, StopsAtTheFirstStepThatChangesTheImageByTheThresholdOrLess) {
    AccuracyBench all(*renderer_, 1);
    auto unlimited = all.converged(still(scene::Mode::dvr), 16, 0.0);
    ASSERT_TRUE(unlimited.ok());
    // A threshold above every change: one step, which changed the image by that much or less.
    AccuracyBench loose(*renderer_, 1);
    auto one = loose.converged(still(scene::Mode::dvr), 16, 255.0);
    ASSERT_TRUE(one.ok());
    EXPECT_EQ(one->steps, 1);
    // A threshold between: more than one step, fewer than the limit, the last change within it.
    const double threshold = 0.5 * (one->last_change + unlimited->last_change);
    AccuracyBench between(*renderer_, 1);
    auto some = between.converged(still(scene::Mode::dvr), 16, threshold);
    ASSERT_TRUE(some.ok());
    EXPECT_GT(some->steps, 1);
    EXPECT_LT(some->steps, 16);
    EXPECT_LE(some->last_change, threshold);
}

TEST_F(ConvergedStillTest, ModesThatCastNoRaysAndUnjitteredStillsDoNotRefine) {
    AccuracyBench bench(*renderer_, 1);
    auto slices = bench.converged(still(scene::Mode::half_angle), 8, 0.0);
    ASSERT_TRUE(slices.ok()) << slices.error().to_string();
    EXPECT_EQ(slices->steps, 0);
    EXPECT_EQ(slices->last.image.pixels, slices->still.image.pixels);
    scene::FrameRequest unjittered = still(scene::Mode::sbrc);
    unjittered.settings.jitter = false;
    auto fixed = bench.converged(unjittered, 8, 0.0);
    ASSERT_TRUE(fixed.ok());
    EXPECT_EQ(fixed->steps, 0);
}

TEST_F(ConvergedStillTest, IsCloserToTheFineStepImageThanTheFirstStill) {
    scene::FrameRequest fine = still(scene::Mode::dvr);
    fine.settings.jitter = false;
    fine.settings.sample_distance /= 16.0;
    auto exact = renderer_->render(fine);
    ASSERT_TRUE(exact.ok());
    AccuracyBench bench(*renderer_, 1);
    auto converged = bench.converged(still(scene::Mode::dvr), 16, 0.0);
    ASSERT_TRUE(converged.ok());
    const base::ImageRgbaF truth = base::to_rgba_f(exact->image);
    const auto first = errors_against(truth, converged->still.image);
    const auto last = errors_against(truth, converged->last.image);
    ASSERT_TRUE(first.ok() && last.ok());
    EXPECT_GT(last->psnr, first->psnr + 3.0)
            << "first still " << first->psnr << " dB, converged " << last->psnr << " dB";
}

}  // namespace
}  // namespace penumbra::quality
