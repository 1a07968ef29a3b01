// Jittered sampling and progressive stills: a coarse step shows rings that jitter turns into noise,
// and averaging the refinement steps on the GPU converges toward the image a much finer step
// gives, in every ray-cast mode.

#include "synthetic_volumes.hpp"

#include <penumbra/imageio/compare.hpp>
#include <penumbra/reference/cpu_renderer.hpp>
#include <penumbra/render/renderer.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace penumbra::render {
namespace {

constexpr std::array<scene::Mode, 6> ray_cast_modes{scene::Mode::dvr,       scene::Mode::phong,
                                                    scene::Mode::sbrc,      scene::Mode::sbrc_shell,
                                                    scene::Mode::sbrc_cone, scene::Mode::reference};

class RefinementTest : public ::testing::Test {
protected:
    void SetUp() override {
        auto created = Renderer::create();
        ASSERT_TRUE(created.ok()) << created.error().to_string();
        renderer_ = std::move(created.value());
        // A smooth ball seen through a steep TF: at a coarse step its shells show as rings.
        volume_ = std::make_shared<const volume::Volume>(test::radial_volume(48));
        ASSERT_TRUE(renderer_->set_volume(volume_).ok());
    }

    static scene::FrameRequest coarse_request(scene::Mode mode) {
        scene::FrameRequest request;
        request.camera = scene::orbit_camera(25.0, 15.0, 2.2);
        request.light.direction = scene::direction_from_angles(-50.0, 30.0);
        request.light.ambient = 0.3;
        // A steep opacity edge: where a ray's first sample past it lands decides how much of the
        // shell it sees, which is what makes the rings of a fixed step.
        request.transfer_function = {"edge",
                                     {{0.0, {0.2, 0.5, 1.0}}, {1.0, {1.0, 0.8, 0.4}}},
                                     {{0.0, 0.0}, {0.4, 0.0}, {0.5, 0.6}, {1.0, 0.6}}};
        scene::RenderSettings& s = request.settings;
        s.mode = mode;
        s.width = 64;
        s.height = 64;
        s.sample_distance = 1.0 / 16.0;
        s.opacity_unit_distance = 1.0 / 64.0;
        s.light_buffer.slices = 32;
        s.light_buffer.resolution = 32;
        return request;
    }

    Frame render(const scene::FrameRequest& request) {
        auto frame = renderer_->render(request);
        EXPECT_TRUE(frame.ok()) << frame.error().to_string();
        return frame.ok() ? std::move(frame.value()) : Frame{};
    }

    static double rms(const Frame& frame, const Frame& reference) {
        auto difference = imageio::compare_images(base::to_rgba_f(frame.image),
                                                  base::to_rgba_f(reference.image));
        EXPECT_TRUE(difference.ok());
        return difference.ok() ? difference->rms_error : 1.0;
    }

    std::unique_ptr<Renderer> renderer_;
    std::shared_ptr<const volume::Volume> volume_;
};

TEST_F(RefinementTest, RefinedStillsConvergeTowardTheFineStepImageInEveryRayCastMode) {
    constexpr int steps = 8;
    for (const scene::Mode mode : ray_cast_modes) {
        SCOPED_TRACE(scene::to_string(mode));
        const scene::FrameRequest unjittered = coarse_request(mode);
        scene::FrameRequest fine = unjittered;
        fine.settings.sample_distance /= 8.0;
        const Frame answer = render(fine);
        const double rings = rms(render(unjittered), answer);

        scene::FrameRequest request = unjittered;
        request.settings.jitter = true;
        request.refinement = {true, 0};
        std::vector<double> errors;
        for (int step = 0; step <= steps; ++step) {
            if (step > 0) {
                request.refinement = {false, step};
            }
            const Frame frame = render(request);
            EXPECT_EQ(frame.report.refinement_step, step);
            errors.push_back(rms(frame, answer));
        }
        // Each step brings the mean closer (up to how unevenly the first steps' offsets cover
        // the step: a step after an evenly spread count cannot keep it even), and eight
        // steps leave clearly less error than the fixed step and than one jittered frame. What
        // remains (0.55-0.8 of the fixed step's error here) is the bias of compositing at the
        // coarse step, which averaging offsets cannot remove.
        for (std::size_t i = 1; i < errors.size(); ++i) {
            EXPECT_LE(errors[i], errors[i - 1] + 0.5 / 255.0) << "step " << i;
        }
        EXPECT_LT(errors.back(), 0.85 * rings)
                << "fixed step " << rings << ", refined " << errors.back();
        EXPECT_LT(errors.back(), 0.85 * errors.front())
                << "one jittered frame " << errors.front() << ", refined " << errors.back();
    }
}

TEST_F(RefinementTest, TheRefinedMeanIsRoundedOnlyOnceNotAtEveryStep) {
    // The CPU renderer samples at the same jittered offsets in double precision, so the mean of
    // its steps is what the GPU's mean should be before its one rounding to 8 bits. Rounding
    // every step before averaging leaves pixels up to a whole level off it (0.69-0.96 levels at
    // steps 1-8 here).
    constexpr int steps = 8;
    constexpr double level = 1.0 / 255.0;
    scene::FrameRequest request = coarse_request(scene::Mode::dvr);
    request.settings.width = 40;
    request.settings.height = 40;
    request.settings.jitter = true;
    request.refinement = {true, 0};
    std::vector<double> exact_sum(std::size_t{4} * 40 * 40, 0.0);
    for (int step = 0; step <= steps; ++step) {
        SCOPED_TRACE("step " + std::to_string(step));
        if (step > 0) {
            request.refinement = {false, step};
        }
        auto exact = reference::render_cpu(*volume_, request);
        ASSERT_TRUE(exact.ok()) << exact.error().to_string();
        const Frame frame = render(request);
        ASSERT_EQ(frame.image.pixels.size(), exact_sum.size());
        // Half a level is the one rounding; the rest allows for float against double.
        double worst = 0.0;
        for (std::size_t i = 0; i < exact_sum.size(); ++i) {
            exact_sum[i] += exact->pixels[i];
            const double exact_mean = exact_sum[i] / (step + 1);
            worst = std::max(worst, std::abs(frame.image.pixels[i] * level - exact_mean) / level);
        }
        EXPECT_LE(worst, 0.6) << "levels from the exact mean";
    }
}

TEST_F(RefinementTest, KeepingAStillFrameDoesNotChangeIt) {
    scene::FrameRequest request = coarse_request(scene::Mode::dvr);
    request.settings.jitter = true;
    const Frame plain = render(request);
    request.refinement = {true, 0};
    const Frame kept = render(request);
    EXPECT_EQ(plain.image.pixels, kept.image.pixels);
    EXPECT_EQ(kept.report.refinement_step, 0);
}

TEST_F(RefinementTest, AStepWithoutItsEarlierStepsIsRefused) {
    scene::FrameRequest request = coarse_request(scene::Mode::dvr);
    request.settings.jitter = true;
    request.refinement = {false, 1};
    auto lost = renderer_->render(request);
    ASSERT_FALSE(lost.ok());
    EXPECT_EQ(lost.error().code, base::ErrorCode::refinement_lost);

    // Kept, then the view changes: the refinement of the old view cannot continue on the new one.
    request.refinement = {true, 0};
    ASSERT_TRUE(renderer_->render(request).ok());
    request.refinement = {false, 1};
    request.camera = scene::orbit_camera(40.0, 15.0, 2.2);
    lost = renderer_->render(request);
    ASSERT_FALSE(lost.ok());
    EXPECT_EQ(lost.error().code, base::ErrorCode::refinement_lost);
}

TEST_F(RefinementTest, RefinementNeedsJitterAndARayCastMode) {
    scene::FrameRequest request = coarse_request(scene::Mode::dvr);
    request.refinement = {true, 0};
    EXPECT_FALSE(renderer_->render(request).ok());
    request.settings.jitter = true;
    request.settings.mode = scene::Mode::half_angle;
    EXPECT_FALSE(renderer_->render(request).ok());
}

TEST_F(RefinementTest, JitterTurnsRingsIntoNoiseWithoutBias) {
    // One jittered frame differs from the unjittered one pixel by pixel, but not on average: the
    // offsets only move where each ray samples within its step.
    const scene::FrameRequest unjittered = coarse_request(scene::Mode::dvr);
    scene::FrameRequest jittered = unjittered;
    jittered.settings.jitter = true;
    const Frame a = render(unjittered);
    const Frame b = render(jittered);
    EXPECT_NE(a.image.pixels, b.image.pixels);
    double mean_a = 0.0;
    double mean_b = 0.0;
    for (std::size_t i = 0; i < a.image.pixels.size(); ++i) {
        mean_a += a.image.pixels[i];
        mean_b += b.image.pixels[i];
    }
    EXPECT_NEAR(mean_a / static_cast<double>(a.image.pixels.size()),
                mean_b / static_cast<double>(b.image.pixels.size()), 1.5);
}

}  // namespace
}  // namespace penumbra::render
