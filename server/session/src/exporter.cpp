#include <penumbra/base/image.hpp>
#include <penumbra/base/log.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/session/exporter.hpp>
#include <penumbra/session/session.hpp>

#include <algorithm>
#include <atomic>
#include <utility>
#include <variant>

namespace penumbra::session {
namespace {

// The smallest tile a still is cut into when its tiles ask for more work than a frame may: below
// it the export fails with the frame's too_much_work.
constexpr int kSmallestTile = 32;

base::Error cancelled_error() {
    return base::make_error(base::ErrorCode::cancelled, "the export was cancelled", "export");
}

}  // namespace

std::string_view to_string(ExportState state) {
    switch (state) {
        case ExportState::running:
            return "running";
        case ExportState::done:
            return "done";
        case ExportState::failed:
            return "failed";
        case ExportState::cancelled:
            return "cancelled";
    }
    return "failed";
}

struct Exporter::Job {
    std::string client;
    std::string key;  // its frames' name in the scheduler
    RenderJob still;
    int max_tile_side = 0;
    std::vector<encode::ImageText> text;
    Progress progress;
    ExportStatus status;  // the job's thread's
    std::atomic<bool> cancelled{false};
    std::atomic<bool> finished{false};
    std::thread thread;

    // The frame waited for: its number, so that an outcome of an earlier one is not taken for it.
    std::mutex mutex;
    std::condition_variable changed;
    std::uint64_t frame = 0;
    std::optional<FrameOutcome> outcome;
};

Exporter::Exporter(Scheduler& scheduler, ExportLimits limits)
    : scheduler_(scheduler)
    , limits_(limits) {}

Exporter::~Exporter() {
    std::vector<std::pair<std::string, std::string>> jobs;  // id, client
    {
        const std::lock_guard lock(mutex_);
        for (const auto& [id, job] : running_) {
            jobs.emplace_back(id, job->client);
        }
    }
    for (const auto& [id, client] : jobs) {
        cancel(id, client);
    }
    std::unique_lock lock(mutex_);
    idle_.wait(lock, [&] { return running_.empty(); });
    for (std::thread& thread : threads_) {
        if (thread.joinable()) {
            thread.join();
        }
    }
}

base::Result<std::string> Exporter::start_still(const std::string& client, RenderJob still,
                                                int max_tile_side, std::string file_name,
                                                const std::string& source,
                                                const std::string& state_json, Progress progress) {
    const scene::RenderSettings& s = still.request.settings;
    if (s.width < 1 || s.height < 1 || s.width > limits_.max_side || s.height > limits_.max_side) {
        return base::make_error(
                base::ErrorCode::out_of_range,
                "an exported still's sides lie within 1.." + std::to_string(limits_.max_side),
                "/width");
    }
    // The job's thread may write its status as soon as it starts: its id is read from here.
    const std::string id = random_secret();
    auto job = std::make_shared<Job>();
    job->client = client;
    job->still = std::move(still);
    job->still.raw = true;
    job->still.stream.reset();
    job->still.preview.reset();
    job->still.interactive = false;
    job->max_tile_side = std::max(kSmallestTile, std::min(max_tile_side, limits_.tile_side));
    job->text = encode::still_text(source, state_json);
    job->progress = std::move(progress);
    job->status.width = s.width;
    job->status.height = s.height;
    job->status.file_name = std::move(file_name);
    {
        const std::lock_guard lock(mutex_);
        // Threads of finished exports are joined here, so that they never pile up: each has
        // nothing left to do but return (finish).
        for (std::thread& thread : threads_) {
            thread.join();
        }
        threads_.clear();
        const auto of_client = std::ranges::count_if(
                running_, [&](const auto& entry) { return entry.second->client == client; });
        if (of_client >= limits_.per_client) {
            return base::make_error(base::ErrorCode::rate_limited,
                                    "this client already has its " +
                                            std::to_string(limits_.per_client) +
                                            " export(s) running: wait for one or cancel it",
                                    "/type");
        }
        if (std::ssize(running_) >= limits_.at_once) {
            return base::make_error(base::ErrorCode::rate_limited,
                                    "the server is rendering its most exports at once (" +
                                            std::to_string(limits_.at_once) + "): try again soon",
                                    "/type");
        }
        job->status.id = id;
        job->key = "export:" + id;
        running_.emplace(id, job);
        job->thread = std::thread([this, job] { run(job); });
    }
    return id;
}

bool Exporter::cancel(const std::string& id, const std::string& client) {
    std::shared_ptr<Job> job;
    {
        const std::lock_guard lock(mutex_);
        const auto found = running_.find(id);
        if (found == running_.end() || found->second->client != client) {
            return false;
        }
        job = found->second;
    }
    {
        const std::lock_guard lock(job->mutex);
        job->cancelled = true;
    }
    job->changed.notify_all();
    scheduler_.cancel(job->key);
    return true;
}

std::optional<ExportFile> Exporter::file(const std::string& id) {
    const std::lock_guard lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    std::erase_if(kept_, [&](const auto& entry) { return entry.second.until < now; });
    const auto found = kept_.find(id);
    if (found == kept_.end()) {
        return std::nullopt;
    }
    return found->second.file;
}

bool Exporter::is_running(const std::string& id) const {
    const std::lock_guard lock(mutex_);
    return running_.contains(id);
}

int Exporter::running() const {
    const std::lock_guard lock(mutex_);
    return static_cast<int>(running_.size());
}

base::Result<std::shared_ptr<const base::ImageRgba8>> Exporter::render(
        const std::shared_ptr<Job>& shared, RenderJob frame) {
    Job& job = *shared;
    std::uint64_t number = 0;
    {
        const std::lock_guard lock(job.mutex);
        if (job.cancelled) {
            return cancelled_error();
        }
        number = ++job.frame;
        job.outcome.reset();
    }
    frame.submitted = Clock::now();
    scheduler_.submit_background(job.key, std::move(frame), [shared, number](FrameOutcome outcome) {
        {
            const std::lock_guard lock(shared->mutex);
            if (shared->frame != number) {
                return;
            }
            shared->outcome = std::move(outcome);
        }
        shared->changed.notify_all();
    });
    std::unique_lock lock(job.mutex);
    job.changed.wait(lock, [&] { return job.outcome.has_value() || job.cancelled; });
    if (job.cancelled) {
        return cancelled_error();
    }
    FrameOutcome outcome = std::move(*job.outcome);
    if (const auto* frame_done = std::get_if<std::shared_ptr<const EncodedFrame>>(&outcome)) {
        return (*frame_done)->pixels;
    }
    if (const auto* failed = std::get_if<FrameFailure>(&outcome)) {
        return failed->error;
    }
    return base::make_error(base::ErrorCode::cancelled, "the server is shutting down", "export");
}

base::Result<base::ImageRgba8> Exporter::render_still(const std::shared_ptr<Job>& shared,
                                                      int tile_side) {
    Job& job = *shared;
    const scene::FrameRequest& whole = job.still.request;
    const std::vector<scene::FrameRequest> tiles = scene::image_tiles(whole, tile_side);
    job.status.tiles = static_cast<int>(tiles.size());
    const double tile_count = static_cast<double>(tiles.size());
    base::ImageRgba8 image(whole.settings.width, whole.settings.height);
    RenderJob frame = job.still;
    for (std::size_t i = 0; i < tiles.size(); ++i) {
        const scene::FrameRequest& tile = tiles[i];
        // Refined as the session's still would be, tile by tile: one tile's mean held at a time.
        std::shared_ptr<const base::ImageRgba8> refined;
        std::optional<double> change;
        for (int step = 0;; ++step) {
            frame.request = step == 0 ? tile : scene::refinement_step_request(tile, step);
            auto rendered = render(shared, frame);
            if (!rendered) {
                return rendered.error();
            }
            if (refined) {
                if (auto measured = base::change_in_levels(*refined, **rendered)) {
                    change = *measured;
                }
            }
            refined = std::move(rendered.value());
            if (!scene::refines_after(step, change, job.still.refinement_steps,
                                      job.still.refinement_threshold)) {
                break;
            }
            job.status.progress =
                    (static_cast<double>(i) +
                     static_cast<double>(step + 1) / (job.still.refinement_steps + 1)) /
                    tile_count;
            job.progress(job.status);
        }
        base::paste(image, *refined, tile.tile.x, tile.tile.y);
        job.status.progress = static_cast<double>(i + 1) / tile_count;
        job.progress(job.status);
    }
    return image;
}

void Exporter::run(const std::shared_ptr<Job>& job) {
    ExportStatus status = job->status;
    int side = job->max_tile_side;
    auto image = render_still(job, side);
    // Smaller tiles where one asked for more work than a frame may (a fine step, the reference).
    while (!image && image.error().code == base::ErrorCode::too_much_work &&
           side / 2 >= kSmallestTile) {
        side /= 2;
        image = render_still(job, side);
    }
    status = job->status;
    if (!image) {
        status.state = image.error().code == base::ErrorCode::cancelled && job->cancelled
                               ? ExportState::cancelled
                               : ExportState::failed;
        status.error = image.error();
        finish(*job, std::move(status));
        return;
    }
    auto png = encode::encode_image(*image, encode::ImageFormat::png, 90, job->text);
    if (!png) {
        status.state = ExportState::failed;
        status.error = png.error();
        finish(*job, std::move(status));
        return;
    }
    status.bytes = png->size();
    keep(status.id, {std::make_shared<const std::vector<std::uint8_t>>(std::move(png.value())),
                     status.file_name, "image/png"});
    status.state = ExportState::done;
    status.progress = 1.0;
    finish(*job, std::move(status));
}

void Exporter::keep(const std::string& id, ExportFile file) {
    const std::lock_guard lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    std::erase_if(kept_, [&](const auto& entry) { return entry.second.until < now; });
    const auto held = [&] {
        std::size_t bytes = 0;
        for (const auto& [kept_id, kept] : kept_) {
            bytes += kept.file.bytes->size();
        }
        return bytes;
    };
    // The oldest go first (the soonest to expire) while the new one would not fit beside them.
    while (!kept_.empty() && held() + file.bytes->size() > limits_.max_bytes_kept) {
        kept_.erase(std::ranges::min_element(kept_, {},
                                             [](const auto& entry) { return entry.second.until; }));
    }
    kept_.insert_or_assign(id, Kept{std::move(file), now + limits_.kept});
}

void Exporter::finish(Job& job, ExportStatus status) {
    if (status.error) {
        base::log_info("export", "export " + status.id.substr(0, 8) + " " +
                                         std::string(to_string(status.state)) + ": " +
                                         status.error->to_string());
    }
    job.status = status;
    {
        // No longer running before anyone hears so: its client may start the next at once.
        const std::lock_guard lock(mutex_);
        // The thread joins later (start_still, the destructor): it cannot join itself. Its last
        // act is the call below, which a join waits for.
        const auto found = running_.find(status.id);
        if (found != running_.end()) {
            threads_.push_back(std::move(found->second->thread));
            running_.erase(found);
        }
        idle_.notify_all();
    }
    job.progress(status);
}

}  // namespace penumbra::session
