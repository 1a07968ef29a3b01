// With frames in flight (a GPU's RendererInfo::frames_in_flight), the render thread submits the
// next frame before it waits for the one before; frames are completed in the order they were
// taken, each session's outcomes reach it in order, none is lost, and closing a session whose
// frame is in flight still withdraws it. A fake renderer stands in for the GPU and logs what it
// is asked.

#include <penumbra/session/scheduler.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace penumbra::session {
namespace {

using namespace std::chrono_literals;

// What the fake renderer was asked, shared with the test. A frame's name is its request's width.
struct RendererLog {
    std::mutex mutex;
    std::vector<std::string> events;  // "submit N", "complete N"
    int outstanding = 0;
    int most_outstanding = 0;
    // Frames whose submit() waits until the test releases them, and says when it started to.
    std::map<int, std::shared_future<void>> held;
    std::map<int, std::shared_ptr<std::promise<void>>> entered;
};

// The image a frame comes back with: its size names the frame.
int width_of(int name) {
    return 1 + name % 13;
}

int height_of(int name) {
    return 1 + name % 7;
}

// Frames whose submit() fails (as a refused request does), and whose complete() fails.
bool fails_at_submit(int name) {
    return name % 11 == 5;
}

bool fails_at_complete(int name) {
    return name % 13 == 9;
}

class PipeliningRenderer final : public render::FrameRenderer {
public:
    PipeliningRenderer(RendererLog& log, int frames_in_flight)
        : log_(log) {
        info_.frames_in_flight = frames_in_flight;
    }

    [[nodiscard]] const render::RendererInfo& info() const override { return info_; }

    base::Status set_volume(std::shared_ptr<const volume::Volume>) override { return base::Ok{}; }

    base::Result<render::Frame> render(const scene::FrameRequest& request,
                                       const render::CancelPredicate& cancelled) override {
        auto submitted = submit(request, cancelled);
        if (!submitted) {
            return submitted.error();
        }
        return complete(std::move(submitted.value()));
    }

    base::Result<render::SubmittedFrame> submit(const scene::FrameRequest& request,
                                                const render::CancelPredicate&) override {
        const int name = request.settings.width;
        std::shared_future<void> gate;
        {
            const std::lock_guard lock(log_.mutex);
            if (const auto held = log_.held.find(name); held != log_.held.end()) {
                gate = held->second;
                log_.entered.at(name)->set_value();
            }
        }
        if (gate.valid()) {
            gate.wait();
        }
        if (fails_at_submit(name)) {
            return base::make_error(base::ErrorCode::invalid_frame, "refused", "render");
        }
        const std::lock_guard lock(log_.mutex);
        log_.events.push_back("submit " + std::to_string(name));
        ++log_.outstanding;
        log_.most_outstanding = std::max(log_.most_outstanding, log_.outstanding);
        const std::uint64_t ticket = ++next_ticket_;
        names_[ticket] = name;
        return render::SubmittedFrame{.ticket = ticket, .rendered = std::nullopt};
    }

    base::Result<render::Frame> complete(render::SubmittedFrame submitted) override {
        const std::lock_guard lock(log_.mutex);
        const auto found = names_.find(submitted.ticket);
        if (found == names_.end()) {
            return base::make_error(base::ErrorCode::internal_error, "no such frame", "render");
        }
        const int name = found->second;
        names_.erase(found);
        log_.events.push_back("complete " + std::to_string(name));
        --log_.outstanding;
        if (fails_at_complete(name)) {
            return base::make_error(base::ErrorCode::gl_error, "lost", "render");
        }
        render::Frame frame;
        frame.image = base::ImageRgba8(width_of(name), height_of(name));
        return frame;
    }

    [[nodiscard]] std::size_t gpu_bytes_held() const override { return 0; }

private:
    RendererLog& log_;
    render::RendererInfo info_;
    std::map<std::uint64_t, int> names_;
    std::uint64_t next_ticket_ = 0;
};

// An outcome as the test compares it: "frame N", "failure N" or "withdrawn".
std::string describe(const FrameOutcome& outcome) {
    if (const auto* frame = std::get_if<std::shared_ptr<const EncodedFrame>>(&outcome)) {
        const int name = static_cast<int>((*frame)->request_id);
        const bool sized_right =
                (*frame)->width == width_of(name) && (*frame)->height == height_of(name);
        return "frame " + std::to_string(name) + (sized_right ? "" : " with another's image");
    }
    if (const auto* failure = std::get_if<FrameFailure>(&outcome)) {
        return "failure " + std::to_string(failure->request_id);
    }
    return "withdrawn";
}

class SchedulerPipelineTest : public ::testing::Test {
protected:
    void start(int device_frames_in_flight, int option_frames_in_flight = 0) {
        SchedulerOptions options;
        options.frames_in_flight = option_frames_in_flight;
        auto created = Scheduler::create(
                [this, device_frames_in_flight]()
                        -> base::Result<std::unique_ptr<render::FrameRenderer>> {
                    return std::unique_ptr<render::FrameRenderer>(
                            std::make_unique<PipeliningRenderer>(log_, device_frames_in_flight));
                },
                options, metrics_);
        ASSERT_TRUE(created.ok()) << created.error().to_string();
        scheduler_ = std::move(created.value());
    }

    // Frame `name` of `session`, asked by `client`; its outcome goes to the future.
    std::future<FrameOutcome> submit(const std::string& session, const std::string& client,
                                     int name) {
        auto promise = std::make_shared<std::promise<FrameOutcome>>();
        auto future = promise->get_future();
        scheduler_->submit(session, job(client, name), [promise](FrameOutcome outcome) {
            promise->set_value(std::move(outcome));
        });
        return future;
    }

    static RenderJob job(const std::string& client, int name) {
        RenderJob job;
        job.request.settings.width = name;
        job.request.settings.height = 1;
        job.request_id = name;
        job.output.format = scene::FrameFormat::png;
        job.client = client;
        return job;
    }

    // Makes frame `name`'s submit() wait for the returned promise; `entered` says when it does.
    std::shared_ptr<std::promise<void>> hold(int name, std::future<void>& entered) {
        auto release = std::make_shared<std::promise<void>>();
        auto started = std::make_shared<std::promise<void>>();
        entered = started->get_future();
        const std::lock_guard lock(log_.mutex);
        log_.held[name] = release->get_future().share();
        log_.entered[name] = started;
        return release;
    }

    std::vector<std::string> events() {
        const std::lock_guard lock(log_.mutex);
        return log_.events;
    }

    RendererLog log_;
    metrics::Registry metrics_;
    std::unique_ptr<Scheduler> scheduler_;
};

TEST_F(SchedulerPipelineTest, TheNextFrameIsSubmittedBeforeTheOneBeforeIsWaitedFor) {
    start(2);
    std::future<void> entered;
    auto release = hold(1, entered);
    auto first = submit("a", "10.0.0.1", 1);
    ASSERT_EQ(entered.wait_for(5s), std::future_status::ready);
    // While frame 1 is being submitted, two more sessions' frames wait.
    auto second = submit("b", "10.0.0.2", 2);
    auto third = submit("c", "10.0.0.3", 3);
    release->set_value();
    for (auto* outcome : {&first, &second, &third}) {
        ASSERT_EQ(outcome->wait_for(5s), std::future_status::ready);
    }
    EXPECT_EQ(describe(first.get()), "frame 1");
    EXPECT_EQ(describe(second.get()), "frame 2");
    EXPECT_EQ(describe(third.get()), "frame 3");
    EXPECT_EQ(events(), (std::vector<std::string>{"submit 1", "submit 2", "complete 1", "submit 3",
                                                  "complete 2", "complete 3"}));
    EXPECT_EQ(log_.most_outstanding, 2);
}

TEST_F(SchedulerPipelineTest, OneFrameInFlightWaitsForEachFrameBeforeTheNext) {
    // A software rasteriser's setting, and the option overriding a GPU's.
    for (const auto& [device, option] : {std::pair{1, 0}, std::pair{2, 1}}) {
        SCOPED_TRACE("device " + std::to_string(device) + ", option " + std::to_string(option));
        log_.events.clear();
        log_.most_outstanding = 0;
        start(device, option);
        std::future<void> entered;
        auto release = hold(1, entered);
        auto first = submit("a", "10.0.0.1", 1);
        ASSERT_EQ(entered.wait_for(5s), std::future_status::ready);
        auto second = submit("b", "10.0.0.2", 2);
        release->set_value();
        ASSERT_EQ(second.wait_for(5s), std::future_status::ready);
        EXPECT_EQ(describe(first.get()), "frame 1");
        EXPECT_EQ(events(),
                  (std::vector<std::string>{"submit 1", "complete 1", "submit 2", "complete 2"}));
        EXPECT_EQ(log_.most_outstanding, 1);
        scheduler_->stop();
        const std::lock_guard lock(log_.mutex);
        log_.held.clear();
        log_.entered.clear();
    }
}

TEST_F(SchedulerPipelineTest, ASessionClosedWhileItsFrameIsInFlightIsWithdrawnAndTheFrameFreed) {
    start(2);
    std::future<void> first_entered;
    std::future<void> third_entered;
    auto release_first = hold(10, first_entered);
    auto release_third = hold(12, third_entered);
    auto first = submit("z", "10.0.0.1", 10);
    ASSERT_EQ(first_entered.wait_for(5s), std::future_status::ready);
    auto closed = submit("a", "10.0.0.2", 11);
    auto third = submit("b", "10.0.0.3", 12);
    release_first->set_value();
    // Frame 11 is submitted and waits to be completed while frame 12 is being submitted.
    ASSERT_EQ(third_entered.wait_for(5s), std::future_status::ready);
    scheduler_->cancel("a");
    release_third->set_value();
    for (auto* outcome : {&first, &closed, &third}) {
        ASSERT_EQ(outcome->wait_for(5s), std::future_status::ready);
    }
    EXPECT_EQ(describe(first.get()), "frame 10");
    EXPECT_EQ(describe(closed.get()), "withdrawn");
    EXPECT_EQ(describe(third.get()), "frame 12");
    const std::vector<std::string> log = events();
    EXPECT_NE(std::find(log.begin(), log.end(), "complete 11"), log.end())
            << "the renderer must still be asked to complete the withdrawn frame";
    EXPECT_EQ(log_.outstanding, 0);
}

// A still whose session asked again while it was being submitted, the newer frame taken and
// submitted before the still completes: the still's refinement steps would refine a view the
// session has left, so none follows.
TEST_F(SchedulerPipelineTest, AStillWhoseSessionMovedOnBeforeItCompletedIsNotRefined) {
    start(2);
    std::future<void> entered;
    auto release = hold(1, entered);
    std::mutex mutex;
    std::vector<std::string> outcomes;
    std::promise<void> both;
    const auto record = [&](FrameOutcome outcome) {
        const std::lock_guard lock(mutex);
        outcomes.push_back(describe(outcome));
        if (outcomes.size() == 2) {
            both.set_value();
        }
    };
    RenderJob still = job("10.0.0.1", 1);
    still.refinement_steps = 4;
    scheduler_->submit("a", still, record);
    ASSERT_EQ(entered.wait_for(5s), std::future_status::ready);
    RenderJob moved = job("10.0.0.1", 2);
    moved.interactive = true;
    scheduler_->submit("a", moved, record);
    release->set_value();
    ASSERT_EQ(both.get_future().wait_for(5s), std::future_status::ready);
    scheduler_->stop();
    const std::lock_guard lock(mutex);
    EXPECT_EQ(outcomes, (std::vector<std::string>{"frame 1", "frame 2"}));
    EXPECT_EQ(events(),
              (std::vector<std::string>{"submit 1", "submit 2", "complete 1", "complete 2"}));
}

// A session's next frame fails when submitted while its frame before is still in flight: the
// failure waits for that frame, as the frame waits for nothing it was submitted before.
TEST_F(SchedulerPipelineTest, AFailureOfTheNextFrameComesAfterTheFrameInFlightBeforeIt) {
    start(2);
    ASSERT_TRUE(fails_at_submit(5));
    std::future<void> entered;
    auto release = hold(1, entered);
    std::mutex mutex;
    std::vector<std::string> outcomes;
    std::promise<void> both;
    const auto record = [&](FrameOutcome outcome) {
        const std::lock_guard lock(mutex);
        outcomes.push_back(describe(outcome));
        if (outcomes.size() == 2) {
            both.set_value();
        }
    };
    scheduler_->submit("a", job("10.0.0.1", 1), record);
    ASSERT_EQ(entered.wait_for(5s), std::future_status::ready);
    scheduler_->submit("a", job("10.0.0.1", 5), record);
    release->set_value();
    ASSERT_EQ(both.get_future().wait_for(5s), std::future_status::ready);
    const std::lock_guard lock(mutex);
    EXPECT_EQ(outcomes, (std::vector<std::string>{"frame 1", "failure 5"}));
    EXPECT_EQ(events(), (std::vector<std::string>{"submit 1", "complete 1"}));
}

// Sessions of several clients ask as fast as they can, some frames failing when submitted and
// some when completed: every request gets exactly one outcome, and each session's frames and
// failures come in the order it asked, each frame with its own image.
TEST_F(SchedulerPipelineTest, UnderChurnEveryRequestGetsOneOutcomeAndEachSessionsComeInOrder) {
    start(2);
    constexpr int kSessions = 6;
    constexpr int kFramesEach = 60;
    std::mutex mutex;
    std::map<std::string, std::vector<std::string>> outcomes;  // by session, as they came
    std::atomic<int> answered = 0;
    std::vector<std::thread> clients;
    for (int s = 0; s < kSessions; ++s) {
        clients.emplace_back([&, s] {
            const std::string session = "s" + std::to_string(s);
            const std::string client = "10.0.0." + std::to_string(1 + s % 3);
            for (int i = 0; i < kFramesEach; ++i) {
                const int name = s * 1000 + i + 1;
                scheduler_->submit(session, job(client, name), [&, session](FrameOutcome o) {
                    {
                        const std::lock_guard lock(mutex);
                        outcomes[session].push_back(describe(o));
                    }
                    ++answered;
                });
                if (i % 5 == 0) {
                    std::this_thread::sleep_for(1ms);
                }
            }
        });
    }
    for (auto& thread : clients) {
        thread.join();
    }
    const auto deadline = Clock::now() + 10s;
    while (answered < kSessions * kFramesEach && Clock::now() < deadline) {
        std::this_thread::sleep_for(5ms);
    }
    ASSERT_EQ(answered, kSessions * kFramesEach) << "an outcome was lost";
    scheduler_->stop();
    EXPECT_EQ(answered, kSessions * kFramesEach) << "an outcome came twice";
    int frames = 0;
    int failures = 0;
    for (const auto& [session, list] : outcomes) {
        SCOPED_TRACE(session);
        int last = 0;
        for (const std::string& outcome : list) {
            if (outcome == "withdrawn") {
                continue;  // replaced by the session's newer request
            }
            EXPECT_EQ(outcome.find("another's"), std::string::npos) << outcome;
            const int name = std::stoi(outcome.substr(outcome.find(' ') + 1));
            EXPECT_GT(name, last) << outcome << " came after " << last;
            last = name;
            const bool failed = outcome.starts_with("failure");
            EXPECT_EQ(failed, fails_at_submit(name) || fails_at_complete(name)) << outcome;
            (failed ? failures : frames) += 1;
        }
        // The session's last request is never replaced: it is answered as itself.
        const int newest = std::stoi(session.substr(1)) * 1000 + kFramesEach;
        EXPECT_EQ(last, newest);
    }
    // Only session 0's newest request fails (at submit): each other session's newest is a frame.
    EXPECT_GE(frames, kSessions - 1);
    EXPECT_LE(log_.most_outstanding, 2);
    std::printf("[ measured ] %d frames and %d failures delivered, the rest withdrawn\n", frames,
                failures);
}

}  // namespace
}  // namespace penumbra::session
