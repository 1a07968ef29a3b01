// The scheduler's queue with a fake renderer that records the order of its frames: render turns go
// round the clients first, then round the sessions of each client (a client with many sessions
// waits its turn like any other); a session's newest request replaces its unrendered older ones
// (latest wins); a frame is encoded while the next one renders.

#include <penumbra/session/scheduler.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <variant>
#include <vector>

namespace penumbra::session {
namespace {

using namespace std::chrono_literals;

// Renders for as many milliseconds as the request's width says and records its height, which the
// test uses to name the job, and when each render started. Its images are `image_side` pixels a
// side of noise, so that a large one takes a while to encode.
class RecordingRenderer final : public render::FrameRenderer {
public:
    RecordingRenderer(std::mutex& mutex, std::vector<int>& order, int image_side = 8,
                      std::vector<Clock::time_point>* started = nullptr)
        : mutex_(mutex)
        , order_(order)
        , image_side_(image_side)
        , started_(started) {}

    [[nodiscard]] const render::RendererInfo& info() const override { return info_; }

    base::Status set_volume(std::shared_ptr<const volume::Volume>) override { return base::Ok{}; }

    base::Result<render::Frame> render(const scene::FrameRequest& request,
                                       const render::CancelPredicate&) override {
        {
            const std::lock_guard lock(mutex_);
            order_.push_back(request.settings.height);
            if (started_ != nullptr) {
                started_->push_back(Clock::now());
            }
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(request.settings.width));
        render::Frame frame;
        frame.image = base::ImageRgba8(image_side_, image_side_);
        std::uint32_t noise = 12345;
        for (auto& value : frame.image.pixels) {
            noise = noise * 1664525U + 1013904223U;
            value = static_cast<std::uint8_t>(noise >> 24);
        }
        return frame;
    }

    [[nodiscard]] std::size_t gpu_bytes_held() const override { return 0; }

private:
    render::RendererInfo info_;
    std::mutex& mutex_;
    std::vector<int>& order_;
    int image_side_;
    std::vector<Clock::time_point>* started_;
};

// A scheduler over a RecordingRenderer, and jobs named by `name` that take `ms` to render.
struct RecordingScheduler {
    explicit RecordingScheduler(int image_side = 8, SchedulerOptions options = {}) {
        auto created = Scheduler::create(
                [this, image_side]() -> base::Result<std::unique_ptr<render::FrameRenderer>> {
                    return std::unique_ptr<render::FrameRenderer>(
                            std::make_unique<RecordingRenderer>(mutex, order, image_side,
                                                                &started));
                },
                options, metrics);
        EXPECT_TRUE(created.ok()) << created.error().to_string();
        scheduler = std::move(created.value());
    }

    // The future gets the job's outcome and when it came.
    std::future<std::pair<FrameOutcome, Clock::time_point>> submit(const std::string& session,
                                                                   const std::string& client,
                                                                   int name, int ms) {
        auto promise = std::make_shared<std::promise<std::pair<FrameOutcome, Clock::time_point>>>();
        auto future = promise->get_future();
        RenderJob job;
        job.request.settings.width = ms;
        job.request.settings.height = name;
        job.output.format = scene::FrameFormat::png;
        job.client = client;
        scheduler->submit(session, std::move(job), [promise](FrameOutcome outcome) {
            promise->set_value({std::move(outcome), Clock::now()});
        });
        return future;
    }

    std::mutex mutex;
    std::vector<int> order;
    std::vector<Clock::time_point> started;
    metrics::Registry metrics;
    std::unique_ptr<Scheduler> scheduler;
};

TEST(SchedulerQueue, ASessionsNewestRequestReplacesItsUnrenderedOlderOnes) {
    RecordingScheduler recording;
    auto busy = recording.submit("other", "10.0.0.9", 0, 200);
    std::this_thread::sleep_for(50ms);
    // While the render thread is busy, one session asks three times: only the last is rendered.
    auto first = recording.submit("a", "10.0.0.1", 1, 1);
    auto second = recording.submit("a", "10.0.0.1", 2, 1);
    auto third = recording.submit("a", "10.0.0.1", 3, 1);
    for (auto* replaced : {&first, &second}) {
        ASSERT_EQ(replaced->wait_for(10s), std::future_status::ready);
        const FrameOutcome outcome = replaced->get().first;
        ASSERT_TRUE(std::holds_alternative<Withdrawn>(outcome));
        EXPECT_EQ(std::get<Withdrawn>(outcome), Withdrawn::superseded);
    }
    ASSERT_EQ(third.wait_for(10s), std::future_status::ready);
    EXPECT_TRUE(std::holds_alternative<std::shared_ptr<const EncodedFrame>>(third.get().first));
    ASSERT_EQ(busy.wait_for(10s), std::future_status::ready);
    const std::lock_guard lock(recording.mutex);
    EXPECT_EQ(recording.order, (std::vector<int>{0, 3}));
    EXPECT_EQ(recording.scheduler->counts().frames, 2U);
}

// The render thread hands a rendered frame to the encoders and takes the next job at once: the
// next frame starts rendering before the first one's (slow, 1024^2 of noise as PNG) encode ends.
TEST(SchedulerQueue, AFrameIsEncodedWhileTheNextOneRenders) {
    RecordingScheduler recording(1024);
    auto busy = recording.submit("gate", "10.0.0.9", 0, 100);
    std::this_thread::sleep_for(20ms);
    auto first = recording.submit("a", "10.0.0.1", 1, 1);
    auto second = recording.submit("b", "10.0.0.2", 2, 1);
    for (auto* job : {&busy, &second}) {
        ASSERT_EQ(job->wait_for(30s), std::future_status::ready);
    }
    ASSERT_EQ(first.wait_for(30s), std::future_status::ready);
    const auto [outcome, encoded_at] = first.get();
    ASSERT_TRUE(std::holds_alternative<std::shared_ptr<const EncodedFrame>>(outcome));
    const auto& frame = std::get<std::shared_ptr<const EncodedFrame>>(outcome);
    const std::lock_guard lock(recording.mutex);
    ASSERT_EQ(recording.order, (std::vector<int>{0, 1, 2}));
    EXPECT_LT(recording.started[2], encoded_at)
            << "the second render waited for the first encode (" << frame->encode_ms << " ms)";
}

TEST(SchedulerFairness, ClientsTakeTurnsBeforeTheSessionsOfOneClientDo) {
    std::mutex mutex;
    std::vector<int> order;
    metrics::Registry metrics;
    auto created = Scheduler::create(
            [&]() -> base::Result<std::unique_ptr<render::FrameRenderer>> {
                return std::unique_ptr<render::FrameRenderer>(
                        std::make_unique<RecordingRenderer>(mutex, order));
            },
            {}, metrics);
    ASSERT_TRUE(created.ok()) << created.error().to_string();
    Scheduler& scheduler = **created;
    std::vector<std::future<void>> finished;
    const auto submit = [&](const std::string& session, const std::string& client, int name,
                            int ms) {
        auto promise = std::make_shared<std::promise<void>>();
        finished.push_back(promise->get_future());
        RenderJob job;
        job.request.settings.width = ms;
        job.request.settings.height = name;
        job.output.format = scene::FrameFormat::png;
        job.client = client;
        scheduler.submit(session, std::move(job), [promise](auto) { promise->set_value(); });
    };
    // The render thread is busy with a long frame while the queue fills: five sessions of one
    // client, then one session each of two others.
    submit("busy", "10.0.0.9", 0, 200);
    std::this_thread::sleep_for(50ms);
    for (int i = 1; i <= 5; ++i) {
        submit("hog" + std::to_string(i), "10.0.0.1", 10 + i, 1);
    }
    submit("polite", "10.0.0.2", 20, 1);
    submit("late", "10.0.0.3", 30, 1);
    for (auto& f : finished) {
        ASSERT_EQ(f.wait_for(10s), std::future_status::ready);
    }
    const std::lock_guard lock(mutex);
    EXPECT_EQ(order, (std::vector<int>{0, 11, 20, 30, 12, 13, 14, 15}));
}

}  // namespace
}  // namespace penumbra::session
