// Progressive stills in the scheduler: the refinement steps of a still frame follow it at the
// lowest priority, and any other job waits for at most one chunk of refinement. A fake renderer
// renders in chunks and counts them, so the test measures queueing in chunks, not in wall time;
// where the test needs a chunk to be in progress when it submits, it holds one at its start.

#include <penumbra/session/scheduler.hpp>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace penumbra::session {
namespace {

using namespace std::chrono_literals;

// Lets the test stop the renderer at the start of a refinement chunk, so that it can submit a job
// while that chunk is in progress and no chunk can finish meanwhile, however busy the machine.
class ChunkGate {
public:
    // Holds the next refinement chunk at its start; true once one is held there, false when none
    // started within `timeout`.
    bool hold(std::chrono::milliseconds timeout) {
        std::unique_lock lock(mutex_);
        hold_ = true;
        return changed_.wait_for(lock, timeout, [this] { return held_; });
    }

    // Lets the held chunk, and every chunk after it, go on.
    void release() {
        {
            const std::lock_guard lock(mutex_);
            hold_ = false;
        }
        changed_.notify_all();
    }

    // Called by the renderer at the start of every refinement chunk.
    void enter_refinement_chunk() {
        std::unique_lock lock(mutex_);
        if (!hold_) {
            return;
        }
        held_ = true;
        changed_.notify_all();
        changed_.wait(lock, [this] { return !hold_; });
        held_ = false;
    }

private:
    std::mutex mutex_;
    std::condition_variable changed_;
    bool hold_ = false;
    bool held_ = false;
};

// Renders request.settings.width chunks of 2 ms, asking between chunks whether to stop, and
// counts the refinement chunks it finished. Each render records the refinement chunks finished
// before it started, its name (the request's height) and its refinement.
class ChunkedRenderer final : public render::FrameRenderer {
public:
    struct Started {
        int name = 0;
        scene::Refinement refinement;
        long long refinement_chunks_before = 0;
    };

    ChunkedRenderer(std::mutex& mutex, std::vector<Started>& started,
                    std::atomic<long long>& refinement_chunks, ChunkGate& gate)
        : mutex_(mutex)
        , started_(started)
        , refinement_chunks_(refinement_chunks)
        , gate_(gate) {}

    [[nodiscard]] const render::RendererInfo& info() const override { return info_; }

    base::Status set_volume(std::shared_ptr<const volume::Volume>) override { return base::Ok{}; }

    base::Result<render::Frame> render(const scene::FrameRequest& request,
                                       const render::CancelPredicate& cancelled) override {
        {
            const std::lock_guard lock(mutex_);
            started_.push_back(
                    {request.settings.height, request.refinement, refinement_chunks_.load()});
        }
        // Every refinement step: the first keeps its frame as the mean's start, the rest average.
        const bool refining = request.refinement.keep || request.refinement.step > 0;
        for (int chunk = 0; chunk < request.settings.width; ++chunk) {
            if (refining) {
                gate_.enter_refinement_chunk();
            }
            std::this_thread::sleep_for(2ms);
            if (refining) {
                ++refinement_chunks_;
            }
            if (cancelled && cancelled()) {
                return base::make_error(base::ErrorCode::cancelled, "cancelled", "render");
            }
        }
        // Each step moves the image less than the one before: 192, 128, 106, 96, 89, 85, ...
        // (changes of 64, 22, 10, 7, 4, ... levels), as a converging mean does. The still is
        // {0, 0}, step 1 {keep, 0}, step k {0, k - 1} (scene::refinement_step_request).
        render::Frame frame;
        frame.image = base::ImageRgba8(8, 8);
        const scene::Refinement& r = request.refinement;
        const int frame_of_still = r.step + (r.keep || r.step > 0 ? 1 : 0);
        const auto level = static_cast<std::uint8_t>(64 + 128 / (frame_of_still + 1));
        for (std::size_t i = 0; i < frame.image.pixels.size(); ++i) {
            frame.image.pixels[i] = i % 4 == 3 ? 255 : level;
        }
        frame.report.refinement_step = r.step;
        return frame;
    }

    [[nodiscard]] std::size_t gpu_bytes_held() const override { return 0; }

private:
    render::RendererInfo info_;
    std::mutex& mutex_;
    std::vector<Started>& started_;
    std::atomic<long long>& refinement_chunks_;
    ChunkGate& gate_;
};

class SchedulerRefinementTest : public ::testing::Test {
protected:
    void SetUp() override {
        auto created = Scheduler::create(
                [this]() -> base::Result<std::unique_ptr<render::FrameRenderer>> {
                    return std::unique_ptr<render::FrameRenderer>(std::make_unique<ChunkedRenderer>(
                            mutex_, started_, refinement_chunks_, gate_));
                },
                {}, metrics_);
        ASSERT_TRUE(created.ok()) << created.error().to_string();
        scheduler_ = std::move(created.value());
    }

    static RenderJob job(int name, int chunks, const std::string& client, bool interactive,
                         int refinement_steps = 0, double refinement_threshold = 0.0) {
        RenderJob job;
        job.refinement_threshold = refinement_threshold;
        job.request.settings.width = chunks;
        job.request.settings.height = name;
        job.output.format = scene::FrameFormat::png;
        job.client = client;
        job.interactive = interactive;
        job.refinement_steps = refinement_steps;
        return job;
    }

    std::vector<ChunkedRenderer::Started> started() {
        const std::lock_guard lock(mutex_);
        return started_;
    }

    metrics::Registry metrics_;
    std::mutex mutex_;
    std::vector<ChunkedRenderer::Started> started_;
    std::atomic<long long> refinement_chunks_{0};
    ChunkGate gate_;
    std::unique_ptr<Scheduler> scheduler_;
};

TEST_F(SchedulerRefinementTest, RefinementStepsFollowAStillFrameUpToTheStepCount) {
    std::mutex frames_mutex;
    std::vector<int> steps;
    std::vector<bool> refining;
    std::promise<void> all;
    scheduler_->submit("a", job(1, 1, "10.0.0.1", false, 3), [&](FrameOutcome outcome) {
        const auto* frame = std::get_if<std::shared_ptr<const EncodedFrame>>(&outcome);
        ASSERT_NE(frame, nullptr);
        const std::lock_guard lock(frames_mutex);
        steps.push_back((*frame)->refinement_step);
        refining.push_back((*frame)->refining);
        if (steps.size() == 4) {
            all.set_value();
        }
    });
    ASSERT_EQ(all.get_future().wait_for(10s), std::future_status::ready);
    std::this_thread::sleep_for(50ms);  // nothing more comes
    const std::lock_guard lock(frames_mutex);
    EXPECT_EQ(steps, (std::vector<int>{0, 1, 2, 3}));
    // Every frame but the last says that another step follows.
    EXPECT_EQ(refining, (std::vector<bool>{true, true, true, false}));
    const auto renders = started();
    ASSERT_EQ(renders.size(), 4u);
    // The first step starts the mean the later ones average into (at a finer step: the still's
    // own frame is not averaged in).
    EXPECT_EQ(renders[0].refinement, (scene::Refinement{false, 0}));
    EXPECT_EQ(renders[1].refinement, (scene::Refinement{true, 0}));
    EXPECT_EQ(renders[3].refinement, (scene::Refinement{false, 2}));
}

TEST_F(SchedulerRefinementTest, RefinementStopsOnceAStepChangesTheImageByTheThresholdOrLess) {
    // The fake's steps change the image by 64, 22, 10, 7, 4, ... levels: with a threshold of 5
    // the fifth step is the last, long before the limit of 20.
    std::mutex frames_mutex;
    std::vector<int> steps;
    std::vector<bool> refining;
    std::promise<void> last;
    scheduler_->submit("a", job(1, 1, "10.0.0.1", false, 20, 5.0), [&](FrameOutcome outcome) {
        const auto* frame = std::get_if<std::shared_ptr<const EncodedFrame>>(&outcome);
        ASSERT_NE(frame, nullptr);
        const std::lock_guard lock(frames_mutex);
        steps.push_back((*frame)->refinement_step);
        refining.push_back((*frame)->refining);
        if (!(*frame)->refining) {
            last.set_value();
        }
    });
    ASSERT_EQ(last.get_future().wait_for(10s), std::future_status::ready);
    std::this_thread::sleep_for(50ms);  // nothing more comes
    const std::lock_guard lock(frames_mutex);
    EXPECT_EQ(steps, (std::vector<int>{0, 1, 2, 3, 4, 5}));
    EXPECT_EQ(refining, (std::vector<bool>{true, true, true, true, true, false}));
    EXPECT_EQ(started().size(), 6u);
}

// A still expected to take too long is previewed (Session::make_job): the preview first, saying
// that more follows, then the still at the lowest priority, kept for its own steps.
TEST_F(SchedulerRefinementTest, APreviewComesFirstThenTheStillAndItsRefinementSteps) {
    RenderJob still = job(1, 1, "10.0.0.1", false, 2);
    still.quality = "the still";
    still.preview = RenderJob::Preview{still.request, "its preview"};
    still.preview->request.settings.height = 2;  // its name
    std::mutex frames_mutex;
    std::vector<bool> previews;
    std::vector<int> steps;
    std::vector<bool> refining;
    std::vector<std::string> qualities;
    std::promise<void> last;
    scheduler_->submit("a", still, [&](FrameOutcome outcome) {
        const auto* frame = std::get_if<std::shared_ptr<const EncodedFrame>>(&outcome);
        ASSERT_NE(frame, nullptr);
        const std::lock_guard lock(frames_mutex);
        previews.push_back((*frame)->preview);
        steps.push_back((*frame)->refinement_step);
        refining.push_back((*frame)->refining);
        qualities.push_back((*frame)->quality);
        if (!(*frame)->refining) {
            last.set_value();
        }
    });
    ASSERT_EQ(last.get_future().wait_for(10s), std::future_status::ready);
    std::this_thread::sleep_for(50ms);  // nothing more comes
    const std::lock_guard lock(frames_mutex);
    EXPECT_EQ(previews, (std::vector<bool>{true, false, false, false}));
    EXPECT_EQ(steps, (std::vector<int>{0, 0, 1, 2}));
    EXPECT_EQ(refining, (std::vector<bool>{true, true, true, false}));
    EXPECT_EQ(qualities,
              (std::vector<std::string>{"its preview", "the still", "the still", "the still"}));
    const auto renders = started();
    ASSERT_EQ(renders.size(), 4u);
    EXPECT_EQ(renders[0].name, 2);
    EXPECT_FALSE(renders[0].refinement.keep) << "the preview is no still to refine";
    EXPECT_EQ(renders[1].name, 1);
    EXPECT_TRUE(renders[2].refinement.keep) << "the still's first step starts the mean";
}

// The still after its preview takes its client's turn as any job does: another client who keeps
// asking for frames gets its share, but cannot hold the still off (a refinement step would yield
// to each of its requests and, with one always pending, never come), and the still is rendered
// once, not restarted.
TEST_F(SchedulerRefinementTest, TheStillAfterItsPreviewTakesItsClientsTurn) {
    RenderJob still = job(1, 50, "10.0.0.1", false, 0);  // 100 ms
    still.preview = RenderJob::Preview{still.request, "preview"};
    still.preview->request.settings.width = 1;
    still.preview->request.settings.height = 2;
    std::atomic<bool> still_done{false};
    std::atomic<int> previews{0};
    scheduler_->submit("a", still, [&](FrameOutcome outcome) {
        const auto* frame = std::get_if<std::shared_ptr<const EncodedFrame>>(&outcome);
        if (frame == nullptr) {
            return;  // withdrawn at shutdown, had the still never come
        }
        if ((*frame)->preview) {
            ++previews;
        } else {
            still_done = true;
        }
    });
    std::atomic<int> other_frames{0};
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    for (int i = 0; !still_done && std::chrono::steady_clock::now() < deadline; ++i) {
        scheduler_->submit("b", job(100, 1, "10.0.0.2", true), [&](FrameOutcome outcome) {
            if (std::holds_alternative<std::shared_ptr<const EncodedFrame>>(outcome)) {
                ++other_frames;
            }
        });
        std::this_thread::sleep_for(1ms);
    }
    scheduler_.reset();  // every callback has run before the counters go
    EXPECT_TRUE(still_done) << "the still never came while another client kept asking";
    EXPECT_EQ(previews.load(), 1);
    EXPECT_GT(other_frames.load(), 0);
    int still_renders = 0;
    for (const auto& render : started()) {
        still_renders += render.name == 1 ? 1 : 0;
    }
    EXPECT_EQ(still_renders, 1) << "the still was restarted";
}

TEST_F(SchedulerRefinementTest, InteractiveFramesAreNotRefined) {
    std::promise<void> done;
    scheduler_->submit("a", job(1, 1, "10.0.0.1", true, 3), [&](auto) { done.set_value(); });
    ASSERT_EQ(done.get_future().wait_for(10s), std::future_status::ready);
    std::this_thread::sleep_for(50ms);
    EXPECT_EQ(started().size(), 1u);
}

TEST_F(SchedulerRefinementTest, OtherSessionsWaitForAtMostOneChunkOfRefinement) {
    // Session "a" refines for a long time (200 steps of 25 chunks); session "b", of another client,
    // drags meanwhile. Each job of b is submitted while a refinement chunk is held at its start, so
    // the chunks finished before b starts are counted from a known point: b may wait for the chunk
    // in progress, and no more. (Reading the count and then submitting, with the renderer running,
    // would blame the scheduler for a chunk that finished before the job was submitted.)
    std::atomic<int> refined{0};
    scheduler_->submit("a", job(1, 25, "10.0.0.1", false, 200), [&](FrameOutcome outcome) {
        const auto* frame = std::get_if<std::shared_ptr<const EncodedFrame>>(&outcome);
        if (frame != nullptr && (*frame)->refinement_step > 0) {
            ++refined;
        }
    });
    for (int i = 0; i < 8; ++i) {
        ASSERT_TRUE(gate_.hold(10s)) << "no refinement chunk started before job " << i;
        const long long chunks_at_submit = refinement_chunks_.load();
        std::promise<void> done;
        scheduler_->submit("b", job(100 + i, 1, "10.0.0.2", i % 2 == 0),
                           [&](auto) { done.set_value(); });
        gate_.release();
        ASSERT_EQ(done.get_future().wait_for(10s), std::future_status::ready);
        for (const auto& render : started()) {
            if (render.name == 100 + i) {
                EXPECT_LE(render.refinement_chunks_before - chunks_at_submit, 1)
                        << "job " << i << " waited for more than one refinement chunk";
            }
        }
    }
    // The preempted step was resumed, not lost: refinement goes on after b is served.
    const int before = refined.load();
    for (int i = 0; i < 1000 && refined.load() == before; ++i) {
        std::this_thread::sleep_for(10ms);
    }
    EXPECT_GT(refined.load(), before);
}

TEST_F(SchedulerRefinementTest, ANewJobOfTheSessionEndsTheRefinementOfItsOldView) {
    std::promise<void> first_refined;
    std::atomic<bool> signalled{false};
    scheduler_->submit("a", job(1, 2, "10.0.0.1", false, 100), [&](FrameOutcome outcome) {
        const auto* frame = std::get_if<std::shared_ptr<const EncodedFrame>>(&outcome);
        if (frame != nullptr && (*frame)->refinement_step > 0 && !signalled.exchange(true)) {
            first_refined.set_value();
        }
    });
    ASSERT_EQ(first_refined.get_future().wait_for(10s), std::future_status::ready);
    std::promise<void> done;
    scheduler_->submit("a", job(2, 1, "10.0.0.1", false, 0), [&](auto) { done.set_value(); });
    ASSERT_EQ(done.get_future().wait_for(10s), std::future_status::ready);
    std::this_thread::sleep_for(50ms);
    const auto renders = started();
    std::size_t new_view = 0;
    while (new_view < renders.size() && renders[new_view].name != 2) {
        ++new_view;
    }
    ASSERT_LT(new_view, renders.size());
    EXPECT_EQ(new_view + 1, renders.size()) << "the old view was refined after the new job";
}

}  // namespace
}  // namespace penumbra::session
