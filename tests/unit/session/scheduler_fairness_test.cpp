// Render turns go round the clients first, then round the sessions of each client: a client with
// many sessions waits its turn like any other. A fake renderer records the order.

#include <penumbra/session/scheduler.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace penumbra::session {
namespace {

using namespace std::chrono_literals;

// Renders for as many milliseconds as the request's width says and records its height, which the
// test uses to name the job.
class RecordingRenderer final : public render::FrameRenderer {
public:
    RecordingRenderer(std::mutex& mutex, std::vector<int>& order)
        : mutex_(mutex)
        , order_(order) {}

    [[nodiscard]] const render::RendererInfo& info() const override { return info_; }

    base::Status set_volume(std::shared_ptr<const volume::Volume>) override { return base::Ok{}; }

    base::Result<render::Frame> render(const scene::FrameRequest& request,
                                       const render::CancelPredicate&) override {
        {
            const std::lock_guard lock(mutex_);
            order_.push_back(request.settings.height);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(request.settings.width));
        render::Frame frame;
        frame.image = base::ImageRgba8(8, 8);
        return frame;
    }

    [[nodiscard]] std::size_t gpu_bytes_held() const override { return 0; }

private:
    render::RendererInfo info_;
    std::mutex& mutex_;
    std::vector<int>& order_;
};

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
        job.output.format = encode::ImageFormat::png;
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
