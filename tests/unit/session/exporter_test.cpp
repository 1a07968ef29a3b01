// Exports: a still larger than a frame, rendered in tiles through the scheduler at the lowest
// priority, each tile refined, put together into a PNG and kept for download; cancelled on
// request; bounded per client and for the server. A fake renderer paints each pixel with its place
// in the whole image, so that the PNG shows whether every tile landed where it belongs.

#include <penumbra/imageio/imageio.hpp>
#include <penumbra/session/exporter.hpp>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace penumbra::session {
namespace {

using namespace std::chrono_literals;

// Paints pixel (x, y) of the whole image as (x mod 256, y mod 256, 64 + 128 / (k + 1)) for the
// still's k-th frame (0: the still; each step moves the image less, as a converging mean does:
// changes of 64, 22, 10, 7, 4, ... levels in blue). Refuses a frame of more pixels than
// `most_pixels` with too_much_work, as the renderer's work ceiling does; takes `frame_ms` in 1 ms
// chunks, asking between them whether to stop; records the sizes and refinements it rendered.
class TileRenderer final : public render::FrameRenderer {
public:
    struct Rendered {
        scene::Tile tile;
        scene::Refinement refinement;
        int width = 0;
        int height = 0;
        glm::dvec3 eye{0.0};
    };

    TileRenderer(std::mutex& mutex, std::vector<Rendered>& rendered, int most_pixels, int frame_ms)
        : mutex_(mutex)
        , rendered_(rendered)
        , most_pixels_(most_pixels)
        , frame_ms_(frame_ms) {}

    [[nodiscard]] const render::RendererInfo& info() const override { return info_; }

    base::Status set_volume(std::shared_ptr<const volume::Volume>) override { return base::Ok{}; }

    base::Result<render::Frame> render(const scene::FrameRequest& request,
                                       const render::CancelPredicate& cancelled) override {
        const scene::RenderSettings& s = request.settings;
        if (s.width * s.height > most_pixels_) {
            return base::make_error(base::ErrorCode::too_much_work, "too much work", "size");
        }
        for (int ms = 0; ms < frame_ms_; ++ms) {
            std::this_thread::sleep_for(1ms);
            if (cancelled && cancelled()) {
                return base::make_error(base::ErrorCode::cancelled, "cancelled", "render");
            }
        }
        {
            const std::lock_guard lock(mutex_);
            rendered_.push_back(
                    {request.tile, request.refinement, s.width, s.height, request.camera.eye});
        }
        render::Frame frame;
        frame.image = base::ImageRgba8(s.width, s.height);
        const scene::Refinement& r = request.refinement;
        const int frame_of_still = r.keep || r.step > 0 ? r.step + 1 : 0;
        const auto blue = static_cast<std::uint8_t>(64 + 128 / (frame_of_still + 1));
        for (int y = 0; y < s.height; ++y) {
            for (int x = 0; x < s.width; ++x) {
                std::uint8_t* p = frame.image.pixel(x, y);
                p[0] = static_cast<std::uint8_t>((request.tile.x + x) % 256);
                p[1] = static_cast<std::uint8_t>((request.tile.y + y) % 256);
                p[2] = blue;
                p[3] = 255;
            }
        }
        return frame;
    }

    [[nodiscard]] std::size_t gpu_bytes_held() const override { return 0; }

private:
    render::RendererInfo info_;
    std::mutex& mutex_;
    std::vector<Rendered>& rendered_;
    int most_pixels_;
    int frame_ms_;
};

// Collects an export's statuses and waits for its last.
class Statuses {
public:
    Exporter::Progress progress() {
        return [this](const ExportStatus& status) {
            {
                const std::lock_guard lock(mutex_);
                all_.push_back(status);
            }
            changed_.notify_all();
        };
    }

    // The last status once it is not `running`; nullopt after 20 s.
    std::optional<ExportStatus> last() {
        std::unique_lock lock(mutex_);
        if (!changed_.wait_for(lock, 20s, [&] {
                return !all_.empty() && all_.back().state != ExportState::running;
            })) {
            return std::nullopt;
        }
        return all_.back();
    }

    bool wait_for_progress() {
        std::unique_lock lock(mutex_);
        return changed_.wait_for(lock, 20s, [&] { return !all_.empty(); });
    }

    std::vector<ExportStatus> all() {
        const std::lock_guard lock(mutex_);
        return all_;
    }

private:
    std::mutex mutex_;
    std::condition_variable changed_;
    std::vector<ExportStatus> all_;
};

class ExporterTest : public ::testing::Test {
protected:
    void start_scheduler(int most_pixels, int frame_ms) {
        auto created = Scheduler::create(
                [this, most_pixels,
                 frame_ms]() -> base::Result<std::unique_ptr<render::FrameRenderer>> {
                    return std::unique_ptr<render::FrameRenderer>(std::make_unique<TileRenderer>(
                            mutex_, rendered_, most_pixels, frame_ms));
                },
                {}, metrics_);
        ASSERT_TRUE(created.ok()) << created.error().to_string();
        scheduler_ = std::move(created.value());
    }

    // A session's still job at the export's size, refined `steps` times (threshold 0: all).
    static RenderJob still(int width, int height, int steps) {
        RenderJob job;
        job.request.settings.width = width;
        job.request.settings.height = height;
        job.request.settings.jitter = true;
        job.refinement_steps = steps;
        job.refinement_threshold = 0.0;
        return job;
    }

    std::vector<TileRenderer::Rendered> rendered() {
        const std::lock_guard lock(mutex_);
        return rendered_;
    }

    metrics::Registry metrics_;
    std::mutex mutex_;
    std::vector<TileRenderer::Rendered> rendered_;
    std::unique_ptr<Scheduler> scheduler_;
};

TEST_F(ExporterTest, AStillIsItsTilesRefinedAndPutTogetherIntoAKeptPng) {
    start_scheduler(64 * 64, 0);
    // Before the exporter, which may still report to it as it goes.
    Statuses statuses;
    Exporter exporter(*scheduler_, {});
    auto id = exporter.start_still("client", still(150, 100, 3), 64, "head.png", "ch2", "{}",
                                   statuses.progress());
    ASSERT_TRUE(id.ok()) << id.error().to_string();
    EXPECT_EQ(id->size(), 32u);
    const auto last = statuses.last();
    ASSERT_TRUE(last.has_value());
    EXPECT_EQ(last->state, ExportState::done);
    EXPECT_EQ(last->tiles, 6);  // 64 + 64 + 22 by 64 + 36
    EXPECT_DOUBLE_EQ(last->progress, 1.0);
    double before = 0.0;
    for (const ExportStatus& status : statuses.all()) {
        EXPECT_GE(status.progress, before);
        before = status.progress;
    }
    // Each tile: the still and three steps, the first of them starting its mean.
    const auto frames = rendered();
    ASSERT_EQ(frames.size(), 24u);
    EXPECT_EQ(frames[0].refinement, (scene::Refinement{false, 0}));
    EXPECT_EQ(frames[1].refinement, (scene::Refinement{true, 0}));
    EXPECT_EQ(frames[3].refinement, (scene::Refinement{false, 2}));
    EXPECT_EQ(frames[4].tile, (scene::Tile{150, 100, 64, 0}));

    const auto file = exporter.file(*id);
    ASSERT_TRUE(file.has_value());
    EXPECT_EQ(file->file_name, "head.png");
    EXPECT_EQ(file->content_type, "image/png");
    EXPECT_EQ(file->bytes->size(), last->bytes);
    auto image = imageio::decode_image(*file->bytes);
    ASSERT_TRUE(image.ok()) << image.error().to_string();
    ASSERT_EQ(image->width, 150);
    ASSERT_EQ(image->height, 100);
    for (int y = 0; y < 100; ++y) {
        for (int x = 0; x < 150; ++x) {
            ASSERT_EQ(image->pixel(x, y)[0], x) << x << "," << y;
            ASSERT_EQ(image->pixel(x, y)[1], y) << x << "," << y;
            ASSERT_EQ(image->pixel(x, y)[2], 64 + 128 / 4) << "each tile's last step, step 3";
        }
    }
    EXPECT_FALSE(exporter.file("0123456789abcdef0123456789abcdef").has_value());
}

// A tile stopped by its own change would stop where its neighbour goes on (a seam in the grain):
// every tile takes the steps the whole view needs, measured on it at a tile's size.
TEST_F(ExporterTest, EveryTileTakesTheStepsTheWholeViewNeeds) {
    start_scheduler(64 * 64, 0);
    // Before the exporter, which may still report to it as it goes.
    Statuses statuses;
    Exporter exporter(*scheduler_, {});
    RenderJob job = still(150, 100, 32);
    // Changes of 36.9, 12.7, 5.8, 4.0 levels (RMS over RGB): the fourth step is the last.
    job.refinement_threshold = 5.0;
    ASSERT_TRUE(exporter.start_still("client", job, 64, "x.png", "ch2", "{}", statuses.progress())
                        .ok());
    const auto last = statuses.last();
    ASSERT_TRUE(last.has_value());
    ASSERT_EQ(last->state, ExportState::done);
    std::map<std::pair<int, int>, int> frames_of_tile;
    int probe = 0;
    for (const TileRenderer::Rendered& frame : rendered()) {
        if (frame.tile.whole()) {
            ++probe;
            EXPECT_EQ(frame.width, 64);  // the view at a tile's size
            EXPECT_EQ(frame.height, 42);
        } else {
            ++frames_of_tile[{frame.tile.x, frame.tile.y}];
        }
    }
    EXPECT_EQ(probe, 5);
    ASSERT_EQ(frames_of_tile.size(), 6u);
    for (const auto& [tile, frames] : frames_of_tile) {
        EXPECT_EQ(frames, 5) << tile.first << "," << tile.second;
    }
}

// A still of one tile stops as a session's still does, where a step changes it little.
TEST_F(ExporterTest, AStillOfOneTileStopsWhereItsImageStopsChanging) {
    start_scheduler(64 * 64, 0);
    // Before the exporter, which may still report to it as it goes.
    Statuses statuses;
    Exporter exporter(*scheduler_, {});
    RenderJob job = still(60, 40, 32);
    job.refinement_threshold = 5.0;  // the fourth step is the last (see above)
    ASSERT_TRUE(exporter.start_still("client", job, 64, "x.png", "ch2", "{}", statuses.progress())
                        .ok());
    const auto last = statuses.last();
    ASSERT_TRUE(last.has_value());
    ASSERT_EQ(last->state, ExportState::done);
    EXPECT_EQ(last->tiles, 1);
    EXPECT_EQ(rendered().size(), 5u) << "the still and four steps, not 32";
}

TEST_F(ExporterTest, AnExportThatCannotFinishInTimeFailsAndGivesItsPlaceBack) {
    start_scheduler(1 << 20, 30);
    ExportLimits limits;
    limits.longest = std::chrono::seconds(1);
    // Before the exporter, which may still report to it as it goes.
    Statuses statuses;
    Exporter exporter(*scheduler_, limits);
    const auto started = std::chrono::steady_clock::now();
    ASSERT_TRUE(exporter.start_still("client", still(64, 64, 200), 64, "x.png", "ch2", "{}",
                                     statuses.progress())
                        .ok());
    const auto last = statuses.last();
    ASSERT_TRUE(last.has_value());
    EXPECT_EQ(last->state, ExportState::failed);
    ASSERT_TRUE(last->error.has_value());
    EXPECT_EQ(last->error->code, base::ErrorCode::render_failed);
    EXPECT_LT(std::chrono::steady_clock::now() - started, 5s);
    EXPECT_EQ(exporter.running(), 0);
}

TEST_F(ExporterTest, TilesShrinkWhereATileAsksForMoreWorkThanAFrameMay) {
    start_scheduler(40 * 40, 0);
    // Before the exporter, which may still report to it as it goes.
    Statuses statuses;
    Exporter exporter(*scheduler_, {});
    ASSERT_TRUE(exporter.start_still("client", still(100, 70, 0), 128, "x.png", "ch2", "{}",
                                     statuses.progress())
                        .ok());
    const auto last = statuses.last();
    ASSERT_TRUE(last.has_value());
    EXPECT_EQ(last->state, ExportState::done);
    EXPECT_EQ(last->tiles, 12);  // 128 and 64 refused; 32: 4 by 3
}

TEST_F(ExporterTest, ACancelledExportStopsKeepsNothingAndLeavesTheSchedulerServing) {
    start_scheduler(1 << 20, 30);
    // Before the exporter, which may still report to it as it goes.
    Statuses statuses;
    Exporter exporter(*scheduler_, {});
    auto id = exporter.start_still("client", still(64, 64, 200), 64, "x.png", "ch2", "{}",
                                   statuses.progress());
    ASSERT_TRUE(id.ok());
    ASSERT_TRUE(statuses.wait_for_progress());
    EXPECT_FALSE(exporter.cancel(*id, "another client"));
    EXPECT_TRUE(exporter.cancel(*id, "client"));
    const auto last = statuses.last();
    ASSERT_TRUE(last.has_value());
    EXPECT_EQ(last->state, ExportState::cancelled);
    EXPECT_LT(last->progress, 0.5);
    EXPECT_FALSE(exporter.file(*id).has_value());
    EXPECT_EQ(exporter.running(), 0);
    // The scheduler renders a session's frame as before.
    std::promise<bool> rendered;
    RenderJob frame = still(8, 8, 0);
    frame.output.format = scene::FrameFormat::png;
    scheduler_->submit("session", frame, [&](const FrameOutcome& outcome) {
        rendered.set_value(std::holds_alternative<std::shared_ptr<const EncodedFrame>>(outcome));
    });
    auto done = rendered.get_future();
    ASSERT_EQ(done.wait_for(10s), std::future_status::ready);
    EXPECT_TRUE(done.get());
}

TEST_F(ExporterTest, ASessionsFramesGoBeforeAnExportsTiles) {
    start_scheduler(1 << 20, 20);
    // Before the exporter, which may still report to it as it goes.
    Statuses statuses;
    Exporter exporter(*scheduler_, {});
    ASSERT_TRUE(exporter.start_still("client", still(64, 64, 20), 64, "x.png", "ch2", "{}",
                                     statuses.progress())
                        .ok());
    ASSERT_TRUE(statuses.wait_for_progress());
    // Four frames of a session, one after the other: none waits for more than the export's frame
    // in flight, which it preempts between chunks.
    for (int i = 0; i < 4; ++i) {
        std::promise<void> rendered;
        const auto submitted = std::chrono::steady_clock::now();
        RenderJob frame = still(9, 9, 0);  // 9x9: told apart from the export's 64x64
        frame.output.format = scene::FrameFormat::png;
        frame.client = "viewer";
        scheduler_->submit("session", frame, [&](const FrameOutcome&) { rendered.set_value(); });
        rendered.get_future().wait();
        // A frame of 20 ms each; well under the export's remaining 15+ frames.
        EXPECT_LT(std::chrono::steady_clock::now() - submitted, 2s);
    }
    const auto last = statuses.last();
    ASSERT_TRUE(last.has_value());
    EXPECT_EQ(last->state, ExportState::done);
}

TEST_F(ExporterTest, ExportsAreBoundedBySizePerClientAndForTheServer) {
    start_scheduler(1 << 20, 20);
    ExportLimits limits;
    limits.max_side = 256;
    limits.per_client = 1;
    limits.at_once = 2;
    // Before the exporter, whose destructor cancels what still runs and reports it to them.
    Statuses a;
    Statuses b;
    Statuses c;
    Exporter exporter(*scheduler_, limits);
    auto too_large =
            exporter.start_still("a", still(257, 10, 0), 64, "x.png", "ch2", "{}", a.progress());
    ASSERT_FALSE(too_large.ok());
    EXPECT_EQ(too_large.error().code, base::ErrorCode::out_of_range);
    ASSERT_TRUE(exporter.start_still("a", still(64, 64, 50), 64, "x.png", "ch2", "{}", a.progress())
                        .ok());
    auto second =
            exporter.start_still("a", still(64, 64, 0), 64, "x.png", "ch2", "{}", a.progress());
    ASSERT_FALSE(second.ok());
    EXPECT_EQ(second.error().code, base::ErrorCode::rate_limited);
    ASSERT_TRUE(exporter.start_still("b", still(64, 64, 50), 64, "x.png", "ch2", "{}", b.progress())
                        .ok());
    auto third =
            exporter.start_still("c", still(64, 64, 0), 64, "x.png", "ch2", "{}", c.progress());
    ASSERT_FALSE(third.ok());
    EXPECT_EQ(third.error().code, base::ErrorCode::rate_limited);
    EXPECT_EQ(exporter.running(), 2);
    // Destroyed while both run: cancelled, joined.
}

TEST_F(ExporterTest, AMovieIsTheViewTurnedFrameByFrameEachRefinedAsTheFirstInAnMp4) {
    start_scheduler(64 * 64, 0);
    // Before the exporter, which may still report to it as it goes.
    Statuses statuses;
    Exporter exporter(*scheduler_, {});
    RenderJob job = still(100, 48, 32);
    job.refinement_threshold = 5.0;  // the fourth step is the last (see above)
    const glm::dvec3 eye = job.request.camera.eye;
    auto id = exporter.start_movie("client", job, {.frames = 4, .rock = 0.0}, 64, "turn.mp4",
                                   statuses.progress());
    ASSERT_TRUE(id.ok()) << id.error().to_string();
    const auto last = statuses.last();
    ASSERT_TRUE(last.has_value());
    ASSERT_EQ(last->state, ExportState::done) << (last->error ? last->error->to_string() : "");
    EXPECT_EQ(last->frames, 4);
    EXPECT_EQ(last->tiles, 2);
    double before = 0.0;
    for (const ExportStatus& status : statuses.all()) {
        EXPECT_GE(status.progress, before);
        before = status.progress;
    }
    // The first frame's probe at a tile's size (the still and four steps), then each frame's two
    // tiles with as many steps; the view turned a quarter each frame about the target.
    const auto frames = rendered();
    ASSERT_EQ(frames.size(), 5u + 4u * 2u * 5u);
    for (std::size_t frame = 0; frame < 4; ++frame) {
        const glm::dvec3 turned = frames[5 + frame * 10].eye;
        EXPECT_NEAR(glm::length(turned), glm::length(eye), 1e-9);
        EXPECT_NEAR(glm::dot(glm::normalize(turned), glm::normalize(eye)),
                    std::cos(glm::radians(90.0 * static_cast<double>(frame))), 1e-9)
                << "frame " << frame;
        for (std::size_t i = 0; i < 10; ++i) {
            EXPECT_EQ(frames[5 + frame * 10 + i].eye, turned) << "one view a frame";
        }
    }
    const auto file = exporter.file(*id);
    ASSERT_TRUE(file.has_value());
    EXPECT_EQ(file->content_type, "video/mp4");
    EXPECT_EQ(file->file_name, "turn.mp4");
    ASSERT_GT(file->bytes->size(), 8u);
    EXPECT_EQ(std::string(file->bytes->begin() + 4, file->bytes->begin() + 8), "ftyp");

    // Odd sides, too many frames, a side too large.
    const auto refused = [&](RenderJob movie_still, int frame_count) {
        auto started =
                exporter.start_movie("other", std::move(movie_still), {.frames = frame_count}, 64,
                                     "x.mp4", statuses.progress());
        return started.ok() ? std::nullopt : std::optional(started.error().code);
    };
    EXPECT_EQ(refused(still(101, 48, 0), 4), base::ErrorCode::invalid_value);
    EXPECT_EQ(refused(still(100, 48, 0), 721), base::ErrorCode::out_of_range);
    EXPECT_EQ(refused(still(100, 48, 0), 0), base::ErrorCode::out_of_range);
    EXPECT_EQ(refused(still(1922, 48, 0), 4), base::ErrorCode::out_of_range);

    // A server that makes no movies refuses them all.
    ExportLimits none;
    none.max_movie_frames = 0;
    Exporter without_movies(*scheduler_, none);
    auto started = without_movies.start_movie("other", still(100, 48, 0), {.frames = 1}, 64,
                                              "x.mp4", statuses.progress());
    ASSERT_FALSE(started.ok());
    EXPECT_EQ(started.error().code, base::ErrorCode::invalid_value);
}

}  // namespace
}  // namespace penumbra::session
