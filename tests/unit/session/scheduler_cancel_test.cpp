// The scheduler cancels the frame in flight when its session is closed, when it stops, and when
// a newer request of the session has waited long enough; a fake renderer stands in for the GPU.

#include <penumbra/session/scheduler.hpp>
#include <penumbra/session/session.hpp>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <memory>
#include <string>
#include <thread>

namespace penumbra::session {
namespace {

using namespace std::chrono_literals;

// "Renders" for as many milliseconds as the request's width says, asking the cancel predicate
// every millisecond, like the real renderer does between chunks.
class SlowRenderer final : public render::FrameRenderer {
public:
    explicit SlowRenderer(std::atomic<int>& started)
        : started_(started) {}

    [[nodiscard]] const render::RendererInfo& info() const override { return info_; }

    base::Status set_volume(std::shared_ptr<const volume::Volume>) override { return base::Ok{}; }

    base::Result<render::Frame> render(const scene::FrameRequest& request,
                                       const render::CancelPredicate& cancelled) override {
        ++started_;
        const auto end = Clock::now() + std::chrono::milliseconds(request.settings.width);
        while (Clock::now() < end) {
            if (cancelled && cancelled()) {
                return base::make_error(base::ErrorCode::cancelled, "cancelled between chunks",
                                        "render");
            }
            std::this_thread::sleep_for(1ms);
        }
        render::Frame frame;
        frame.image = base::ImageRgba8(8, 8);
        return frame;
    }

    [[nodiscard]] std::size_t gpu_bytes_held() const override { return 0; }

private:
    render::RendererInfo info_;
    std::atomic<int>& started_;
};

using Outcome = FrameOutcome;

class SchedulerCancelTest : public ::testing::Test {
protected:
    void start(SchedulerOptions options) {
        auto created = Scheduler::create(
                [this]() -> base::Result<std::unique_ptr<render::FrameRenderer>> {
                    return std::unique_ptr<render::FrameRenderer>(
                            std::make_unique<SlowRenderer>(started_));
                },
                options, metrics_);
        ASSERT_TRUE(created.ok()) << created.error().to_string();
        scheduler_ = std::move(created.value());
    }

    // Submits a frame that takes `ms` to render; the future gets its outcome.
    std::future<Outcome> submit(const std::string& session, int ms) {
        auto promise = std::make_shared<std::promise<Outcome>>();
        auto future = promise->get_future();
        RenderJob job;
        job.request.settings.width = ms;
        job.request.settings.height = 1;
        job.output.format = scene::FrameFormat::png;
        scheduler_->submit(session, std::move(job),
                           [promise](Outcome outcome) { promise->set_value(std::move(outcome)); });
        return future;
    }

    void wait_until_started(int count) {
        const auto deadline = Clock::now() + 5s;
        while (started_ < count && Clock::now() < deadline) {
            std::this_thread::sleep_for(1ms);
        }
        ASSERT_GE(started_, count);
    }

    static std::string code_of(std::future<Outcome>& future, std::chrono::seconds within) {
        if (future.wait_for(within) != std::future_status::ready) {
            return "still rendering";
        }
        const Outcome outcome = future.get();
        if (const auto* withdrawn = std::get_if<Withdrawn>(&outcome)) {
            return *withdrawn == Withdrawn::superseded ? "superseded" : "shutting_down";
        }
        if (const auto* failure = std::get_if<FrameFailure>(&outcome)) {
            return std::string(base::name_of(failure->error.code));
        }
        return "frame";
    }

    metrics::Registry metrics_;
    std::atomic<int> started_{0};
    std::unique_ptr<Scheduler> scheduler_;
};

// Each long frame would take 60 s; each must be answered within 5 s of what cancelled it.
TEST_F(SchedulerCancelTest, NewerRequestOfTheSessionCancelsItsLongFrame) {
    start({.encode_threads = 1, .supersede_running_after = 0ms});
    auto long_frame = submit("a", 60000);
    wait_until_started(1);
    auto newer = submit("a", 1);
    EXPECT_EQ(code_of(long_frame, 5s), "superseded");
    EXPECT_EQ(code_of(newer, 5s), "frame");
}

TEST_F(SchedulerCancelTest, NewerRequestLetsAShortFrameFinish) {
    start({.encode_threads = 1, .supersede_running_after = 10s});
    auto first = submit("a", 200);
    wait_until_started(1);
    auto newer = submit("a", 1);
    EXPECT_EQ(code_of(first, 5s), "frame");
    EXPECT_EQ(code_of(newer, 5s), "frame");
}

TEST_F(SchedulerCancelTest, AnotherSessionsRequestCancelsNothing) {
    start({.encode_threads = 1, .supersede_running_after = 0ms});
    auto first = submit("a", 300);
    wait_until_started(1);
    auto other = submit("b", 1);
    EXPECT_EQ(code_of(first, 5s), "frame");
    EXPECT_EQ(code_of(other, 5s), "frame");
}

TEST_F(SchedulerCancelTest, ClosingTheSessionCancelsItsFrame) {
    start({.encode_threads = 1});
    auto long_frame = submit("a", 60000);
    wait_until_started(1);
    scheduler_->cancel("a");
    EXPECT_EQ(code_of(long_frame, 5s), "superseded");
    auto next = submit("b", 1);
    EXPECT_EQ(code_of(next, 5s), "frame");
}

// Leaving is one call of the registry's: the last viewer out also withdraws the session's frame;
// a viewer leaving while another stays withdraws nothing.
TEST_F(SchedulerCancelTest, TheLastViewerLeavingASessionCancelsItsFrame) {
    start({.encode_threads = 1});
    constexpr ViewerId owner = 1;
    constexpr ViewerId viewer = 2;
    SessionRegistry registry(4);
    auto created = registry.create("v", nullptr, {}, owner);
    ASSERT_TRUE(created.ok());
    const std::shared_ptr<Session> session = *created;
    ASSERT_TRUE(registry.enter(session->id(),
                               [](Session& s) { return s.add_viewer(viewer, {}, {}, {}); })
                        .ok());
    auto long_frame = submit(session->id(), 60000);
    wait_until_started(1);
    EXPECT_FALSE(registry.leave(*session, owner, *scheduler_));
    EXPECT_EQ(code_of(long_frame, 1s), "still rendering") << "a viewer still watches it";
    EXPECT_TRUE(registry.leave(*session, viewer, *scheduler_));
    EXPECT_EQ(code_of(long_frame, 5s), "superseded");
}

TEST_F(SchedulerCancelTest, StoppingCancelsTheFrameInFlight) {
    start({.encode_threads = 1});
    auto long_frame = submit("a", 60000);
    wait_until_started(1);
    const auto start = Clock::now();
    scheduler_->stop();
    EXPECT_LT(Clock::now() - start, 5s);
    EXPECT_EQ(code_of(long_frame, 0s), "shutting_down");
}

}  // namespace
}  // namespace penumbra::session
