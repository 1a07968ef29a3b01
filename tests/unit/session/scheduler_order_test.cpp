// A session's outcomes reach its client in the order their requests were taken, frames and
// failures alike: a failure is not handed on while a frame before it is still being encoded.

#include <penumbra/session/scheduler.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace penumbra::session {
namespace {

using namespace std::chrono_literals;

constexpr int kPreviewName = 2;  // the request's height names it

// The preview (a request of height kPreviewName) comes out as a large frame of noise, which takes
// a PNG encoder tens of milliseconds; any other request fails at once.
class PreviewThenFailingRenderer final : public render::FrameRenderer {
public:
    [[nodiscard]] const render::RendererInfo& info() const override { return info_; }

    base::Status set_volume(std::shared_ptr<const volume::Volume>) override { return base::Ok{}; }

    base::Result<render::Frame> render(const scene::FrameRequest& request,
                                       const render::CancelPredicate&) override {
        if (request.settings.height != kPreviewName) {
            return base::make_error(base::ErrorCode::gl_error, "the still failed", "render");
        }
        render::Frame frame;
        frame.image = base::ImageRgba8(1024, 1024);
        std::uint32_t state = 12345;
        for (auto& byte : frame.image.pixels) {
            state = state * 1664525u + 1013904223u;
            byte = static_cast<std::uint8_t>(state >> 24);
        }
        return frame;
    }

    [[nodiscard]] std::size_t gpu_bytes_held() const override { return 0; }

private:
    render::RendererInfo info_;
};

TEST(SchedulerOrder, AStillThatFailsAfterItsPreviewReachesTheClientAfterThePreview) {
    metrics::Registry metrics;
    auto created = Scheduler::create(
            []() -> base::Result<std::unique_ptr<render::FrameRenderer>> {
                return std::unique_ptr<render::FrameRenderer>(
                        std::make_unique<PreviewThenFailingRenderer>());
            },
            {}, metrics);
    ASSERT_TRUE(created.ok()) << created.error().to_string();
    std::unique_ptr<Scheduler> scheduler = std::move(created.value());

    RenderJob still;
    still.request.settings.width = 1;
    still.request.settings.height = 1;
    still.output.format = scene::FrameFormat::png;
    still.client = "10.0.0.1";
    still.preview = RenderJob::Preview{still.request, "preview"};
    still.preview->request.settings.height = kPreviewName;
    std::mutex mutex;
    std::vector<std::string> outcomes;
    std::promise<void> both;
    scheduler->submit("a", still, [&](FrameOutcome outcome) {
        const std::lock_guard lock(mutex);
        if (std::holds_alternative<std::shared_ptr<const EncodedFrame>>(outcome)) {
            outcomes.emplace_back("frame");
        } else if (std::holds_alternative<FrameFailure>(outcome)) {
            outcomes.emplace_back("failure");
        } else {
            outcomes.emplace_back("withdrawn");
        }
        if (outcomes.size() == 2) {
            both.set_value();
        }
    });
    ASSERT_EQ(both.get_future().wait_for(10s), std::future_status::ready);
    scheduler->stop();
    const std::lock_guard lock(mutex);
    EXPECT_EQ(outcomes, (std::vector<std::string>{"frame", "failure"}));
}

}  // namespace
}  // namespace penumbra::session
