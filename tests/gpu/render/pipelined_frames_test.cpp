// Frames in flight (Renderer::submit before the frame before is complete): each comes back with
// its own pixels, bit for bit those it has when rendered alone, whatever was submitted after it,
// including a progressive still's next step that averages into what the still left on the GPU.

#include "synthetic_volumes.hpp"

#include <penumbra/render/renderer.hpp>

#include <gtest/gtest.h>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace penumbra::render {
namespace {

class PipelinedFramesTest : public ::testing::Test {
protected:
    void SetUp() override {
        auto created = Renderer::create();
        ASSERT_TRUE(created.ok()) << created.error().to_string();
        renderer_ = std::move(created.value());
        volume_ = std::make_shared<const volume::Volume>(test::radial_volume(40));
        ASSERT_TRUE(renderer_->set_volume(volume_).ok());
    }

    static scene::FrameRequest request(scene::Mode mode, double azimuth, int width, int height) {
        scene::FrameRequest r;
        r.camera = scene::orbit_camera(azimuth, 15.0, 2.2);
        r.light.direction = scene::direction_from_angles(-50.0 + azimuth, 30.0);
        r.light.ambient = 0.3;
        r.transfer_function = {"edge",
                               {{0.0, {0.2, 0.5, 1.0}}, {1.0, {1.0, 0.8, 0.4}}},
                               {{0.0, 0.0}, {0.3, 0.0}, {0.6, 0.5}, {1.0, 0.7}}};
        scene::RenderSettings& s = r.settings;
        s.mode = mode;
        s.width = width;
        s.height = height;
        s.sample_distance = 1.0 / 64.0;
        s.light_buffer.slices = 32;
        s.light_buffer.resolution = 32;
        return r;
    }

    base::ImageRgba8 alone(const scene::FrameRequest& r) {
        auto frame = renderer_->render(r);
        EXPECT_TRUE(frame.ok()) << frame.error().to_string();
        return frame.ok() ? std::move(frame->image) : base::ImageRgba8{};
    }

    static std::size_t pixels_differing(const base::ImageRgba8& a, const base::ImageRgba8& b) {
        if (a.width != b.width || a.height != b.height) {
            return static_cast<std::size_t>(-1);
        }
        std::size_t differing = 0;
        for (std::size_t i = 0; i < a.pixels.size(); i += 4) {
            for (std::size_t c = 0; c < 4; ++c) {
                if (a.pixels[i + c] != b.pixels[i + c]) {
                    ++differing;
                    break;
                }
            }
        }
        return differing;
    }

    std::unique_ptr<Renderer> renderer_;
    std::shared_ptr<const volume::Volume> volume_;
};

TEST_F(PipelinedFramesTest, FramesInFlightComeBackEachWithItsOwnPixels) {
    // Modes with and without a light buffer (the second sbrc light moves, so it builds another),
    // half-angle slicing, and sizes that differ, so that no two frames could share a readback.
    std::vector<scene::FrameRequest> requests{request(scene::Mode::sbrc, 20.0, 64, 48),
                                              request(scene::Mode::dvr, 60.0, 40, 72),
                                              request(scene::Mode::sbrc, 100.0, 64, 64),
                                              request(scene::Mode::half_angle, 140.0, 56, 56)};
    // In flight first, so that they build their light buffers (rendered alone afterwards, they
    // reuse them: the same pixels either way).
    std::vector<SubmittedFrame> in_flight;
    for (const auto& r : requests) {
        auto submitted = renderer_->submit(r, [] { return false; });
        ASSERT_TRUE(submitted.ok()) << submitted.error().to_string();
        in_flight.push_back(std::move(submitted.value()));
    }
    // Four wait already: a fifth is refused, not lost.
    auto fifth = renderer_->submit(requests[0], {});
    ASSERT_FALSE(fifth.ok());
    EXPECT_EQ(fifth.error().code, base::ErrorCode::internal_error) << fifth.error().to_string();

    std::vector<Frame> completed;
    for (auto& submitted : in_flight) {
        auto frame = renderer_->complete(std::move(submitted));
        ASSERT_TRUE(frame.ok()) << frame.error().to_string();
        completed.push_back(std::move(frame.value()));
    }
    for (std::size_t i = 0; i < requests.size(); ++i) {
        SCOPED_TRACE("frame " + std::to_string(i) + " (" +
                     std::string(scene::to_string(requests[i].settings.mode)) + ")");
        const Frame* frame = &completed[i];
        EXPECT_EQ(pixels_differing(frame->image, alone(requests[i])), 0u);
        if (requests[i].settings.mode == scene::Mode::sbrc) {
            EXPECT_EQ(frame->report.light_buffer, LightBufferState::built);
        }
        // The pass that drew the pixels and the readback are timed when the frame completes.
        ASSERT_GE(frame->report.passes.size(), 2u);
        const PassTiming& drawn = frame->report.passes[frame->report.passes.size() - 2];
        EXPECT_EQ(drawn.name,
                  requests[i].settings.mode == scene::Mode::half_angle ? "half_angle" : "raycast");
        EXPECT_GT(drawn.wall_ms, 0.0);
        EXPECT_EQ(frame->report.passes.back().name, "readback");
        EXPECT_GE(frame->report.passes.back().wall_ms, 0.0);
    }
    // Completed twice: the renderer no longer has it.
    auto again = renderer_->complete(SubmittedFrame{.ticket = 1, .rendered = std::nullopt});
    EXPECT_FALSE(again.ok());
}

TEST_F(PipelinedFramesTest, AStillsNextStepSubmittedBeforeTheStillCompletesAveragesTheStill) {
    scene::FrameRequest still = request(scene::Mode::sbrc, 30.0, 64, 64);
    still.settings.jitter = true;
    still.refinement = {true, 0};
    const scene::FrameRequest step1 = scene::refinement_step_request(still, 1);
    const scene::FrameRequest step2 = scene::refinement_step_request(still, 2);
    auto a = renderer_->submit(still, {});
    auto b = renderer_->submit(step1, {});
    auto c = renderer_->submit(step2, {});
    ASSERT_TRUE(a.ok() && b.ok() && c.ok());
    auto still_frame = renderer_->complete(std::move(a.value()));
    auto step1_frame = renderer_->complete(std::move(b.value()));
    auto step2_frame = renderer_->complete(std::move(c.value()));
    ASSERT_TRUE(still_frame.ok() && step1_frame.ok() && step2_frame.ok());
    const base::ImageRgba8 still_alone = alone(still);
    const base::ImageRgba8 step1_alone = alone(step1);
    const base::ImageRgba8 step2_alone = alone(step2);
    ASSERT_GT(pixels_differing(step1_alone, step2_alone), 0u) << "the steps must differ";
    EXPECT_EQ(pixels_differing(still_frame->image, still_alone), 0u);
    EXPECT_EQ(pixels_differing(step1_frame->image, step1_alone), 0u);
    EXPECT_EQ(pixels_differing(step2_frame->image, step2_alone), 0u);
    EXPECT_EQ(step2_frame->report.refinement_step, 1);
}

}  // namespace
}  // namespace penumbra::render
