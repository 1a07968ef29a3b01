#include <penumbra/base/image.hpp>
#include <penumbra/base/log.hpp>
#include <penumbra/encode/movie.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/scene/turntable.hpp>
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
    std::optional<MovieSpec> movie;
    int max_tile_side = 0;
    std::vector<encode::ImageText> text;
    Progress progress;
    ExportStatus status;  // the job's thread's
    std::atomic<bool> cancelled{false};
    std::chrono::seconds longest{0};  // how long it may take: ExportLimits::longest(_movie)
    Clock::time_point deadline;
    Clock::time_point reported;  // a movie's last status within a frame
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
    shutdown();
}

void Exporter::shutdown() {
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
        thread.join();
    }
    threads_.clear();
}

namespace {

// The sides of an export's image, checked against its largest.
base::Status check_sides(const RenderJob& job, int max_side, const std::string& what) {
    for (const auto& [side, where] : {std::pair{job.request.settings.width, "/width"},
                                      std::pair{job.request.settings.height, "/height"}}) {
        if (side < 1 || side > max_side) {
            return base::make_error(base::ErrorCode::out_of_range,
                                    what + "'s sides lie within 1.." + std::to_string(max_side),
                                    where);
        }
    }
    return base::Ok{};
}

}  // namespace

base::Result<std::string> Exporter::start_still(const std::string& client, RenderJob still,
                                                int max_tile_side, std::string file_name,
                                                const std::string& source,
                                                const std::string& state_json, Progress progress) {
    if (auto checked = check_sides(still, limits_.max_side, "an exported still"); !checked) {
        return checked.error();
    }
    auto job = std::make_shared<Job>();
    job->client = client;
    job->still = std::move(still);
    job->max_tile_side = max_tile_side;
    job->text = encode::still_text(source, state_json);
    job->progress = std::move(progress);
    job->status.file_name = std::move(file_name);
    return start(std::move(job));
}

base::Result<std::string> Exporter::start_movie(const std::string& client, RenderJob still,
                                                MovieSpec movie, int max_tile_side,
                                                std::string file_name, Progress progress) {
    if (!encode::writes_movies() || limits_.max_movie_frames < 1) {
        return base::make_error(base::ErrorCode::invalid_value,
                                "this server makes no movies (hello.limits.max_movie_frames is 0)",
                                "/type");
    }
    if (auto checked = check_sides(still, limits_.max_movie_side, "a movie"); !checked) {
        return checked.error();
    }
    for (const auto& [side, where] : {std::pair{still.request.settings.width, "/width"},
                                      std::pair{still.request.settings.height, "/height"}}) {
        if (side % 2 != 0) {
            return base::make_error(base::ErrorCode::invalid_value,
                                    "a movie's sides are even (its colour is stored at half the "
                                    "resolution)",
                                    where);
        }
    }
    if (movie.frames < 1 || movie.frames > limits_.max_movie_frames) {
        return base::make_error(
                base::ErrorCode::out_of_range,
                "a movie has 1.." + std::to_string(limits_.max_movie_frames) + " frames",
                "/frames");
    }
    auto job = std::make_shared<Job>();
    job->client = client;
    job->still = std::move(still);
    job->movie = movie;
    job->max_tile_side = max_tile_side;
    job->progress = std::move(progress);
    job->status.file_name = std::move(file_name);
    job->status.frames = movie.frames;
    return start(std::move(job));
}

base::Result<std::string> Exporter::start(std::shared_ptr<Job> job) {
    // The job's thread may write its status as soon as it starts: its id is read from here.
    const std::string id = random_secret();
    job->still.raw = true;
    job->still.stream.reset();
    job->still.preview.reset();
    job->still.interactive = false;
    job->max_tile_side = std::max(kSmallestTile, std::min(job->max_tile_side, limits_.tile_side));
    job->status.width = job->still.request.settings.width;
    job->status.height = job->still.request.settings.height;
    job->longest = job->movie ? limits_.longest_movie : limits_.longest;
    job->deadline = Clock::now() + job->longest;
    const std::string& client = job->client;
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
        // Its first word before any other can be said: a fast failure must not overtake it.
        job->progress(job->status);
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
    const bool answered = job.changed.wait_until(
            lock, job.deadline, [&] { return job.outcome.has_value() || job.cancelled; });
    if (job.cancelled) {
        return cancelled_error();
    }
    if (!answered) {
        // A busy server preempts an export's tiles again and again: it gives up in the end
        // rather than hold its place among the exports.
        lock.unlock();
        scheduler_.cancel(job.key);
        return base::make_error(base::ErrorCode::render_failed,
                                "the export did not finish in " +
                                        std::to_string(job.longest.count()) +
                                        " s: the server is busy; try again later, or smaller",
                                "export");
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

base::Result<Exporter::Refined> Exporter::refine(const std::shared_ptr<Job>& job,
                                                 const scene::FrameRequest& still, int most_steps,
                                                 double threshold,
                                                 const std::function<void(int)>& stepped) {
    RenderJob frame = job->still;
    Refined refined;
    std::optional<double> change;
    for (int step = 0;; ++step) {
        frame.request = step == 0 ? still : scene::refinement_step_request(still, step);
        auto rendered = render(job, frame);
        if (!rendered) {
            return rendered.error();
        }
        if (refined.image) {
            if (auto measured = base::change_in_levels(*refined.image, **rendered)) {
                change = *measured;
            }
        }
        refined = {std::move(rendered.value()), step};
        if (!scene::refines_after(step, change, most_steps, threshold)) {
            return refined;
        }
        stepped(step);
    }
}

base::Result<Exporter::ViewRendered> Exporter::render_view(
        const std::shared_ptr<Job>& shared, const scene::FrameRequest& view, int tile_side,
        int steps, double threshold, const std::function<void(double)>& progressed) {
    Job& job = *shared;
    const std::vector<scene::FrameRequest> tiles = scene::image_tiles(view, tile_side);
    job.status.tiles = static_cast<int>(tiles.size());
    const double tile_count = static_cast<double>(tiles.size());
    // Every tile takes the same refinement steps, lest the grain change at a tile's edge: as many
    // as the whole view needs, measured on it at a tile's size (a tile stopped by its own change,
    // mostly background, would stop long before a busy neighbour).
    if (tiles.size() > 1 && steps > 0 && threshold > 0.0) {
        scene::FrameRequest small = view;
        const double shrink =
                std::min(1.0, static_cast<double>(tile_side) /
                                      std::max(view.settings.width, view.settings.height));
        small.settings.width = std::max(1, static_cast<int>(view.settings.width * shrink));
        small.settings.height = std::max(1, static_cast<int>(view.settings.height * shrink));
        auto probe = refine(shared, small, steps, threshold, [](int) {});
        if (!probe) {
            return probe.error();
        }
        steps = probe->steps;
        threshold = 0.0;
    }
    ViewRendered rendered{base::ImageRgba8(view.settings.width, view.settings.height), 0};
    for (std::size_t i = 0; i < tiles.size(); ++i) {
        const auto stepped = [&](int step) {
            progressed((static_cast<double>(i) + static_cast<double>(step + 1) / (steps + 1)) /
                       tile_count);
        };
        // One tile's mean held at a time; a mean the renderer had to evict (other stills took its
        // memory) is begun again, once.
        auto refined = refine(shared, tiles[i], steps, threshold, stepped);
        if (!refined && refined.error().code == base::ErrorCode::refinement_lost) {
            refined = refine(shared, tiles[i], steps, threshold, stepped);
        }
        if (!refined) {
            return refined.error();
        }
        base::paste(rendered.image, *refined->image, tiles[i].tile.x, tiles[i].tile.y);
        rendered.steps = std::max(rendered.steps, refined->steps);
        progressed(static_cast<double>(i + 1) / tile_count);
    }
    return rendered;
}

base::Result<ExportFile> Exporter::make_still(const std::shared_ptr<Job>& shared, int tile_side) {
    Job& job = *shared;
    auto view = render_view(shared, job.still.request, tile_side, job.still.refinement_steps,
                            job.still.refinement_threshold, [&](double done) {
                                job.status.progress = done;
                                job.progress(job.status);
                            });
    if (!view) {
        return view.error();
    }
    auto png = encode::encode_image(view->image, encode::ImageFormat::png, 90, job.text);
    if (!png) {
        return png.error();
    }
    if (png->size() > limits_.max_bytes_kept) {
        return base::make_error(base::ErrorCode::too_large,
                                "the PNG (" + std::to_string(png->size() >> 20) +
                                        " MiB) is larger than the server keeps",
                                "export");
    }
    return ExportFile{std::make_shared<const std::vector<std::uint8_t>>(std::move(png.value())),
                      job.status.file_name, "image/png"};
}

base::Result<ExportFile> Exporter::make_movie(const std::shared_ptr<Job>& shared, int tile_side) {
    Job& job = *shared;
    const MovieSpec& spec = *job.movie;
    const scene::FrameRequest& still = job.still.request;
    // One thread and a short look ahead: the encoder works beside the sessions' own.
    auto movie = encode::MovieWriter::create_in_memory(
            still.settings.width, still.settings.height,
            {.frames_per_second = spec.frames_per_second,
             .quality = spec.quality,
             .threads = 1,
             .lookahead_frames = 8},
            limits_.max_bytes_kept /
                    static_cast<std::size_t>(std::max(1, limits_.movie_share_of_kept)));
    if (!movie) {
        return movie.error();
    }
    // The first frame decides every frame's refinement steps.
    int steps = job.still.refinement_steps;
    double threshold = job.still.refinement_threshold;
    for (int k = 0; k < spec.frames; ++k) {
        const scene::FrameRequest turned = scene::turntable_frame(still, k, spec.frames, spec.rock);
        // Its status once a frame, and within one at most once a second: every step of every
        // tile of hundreds of frames would flood the connection.
        auto frame = render_view(shared, turned, tile_side, steps, threshold, [&](double done) {
            job.status.progress = (k + done) / spec.frames;
            const Clock::time_point now = Clock::now();
            if (done >= 1.0 || now - job.reported >= std::chrono::seconds(1)) {
                job.reported = now;
                job.progress(job.status);
            }
        });
        if (!frame) {
            return frame.error();
        }
        steps = frame->steps;
        threshold = 0.0;
        if (auto added = movie->add(frame->image); !added) {
            return added.error();
        }
    }
    if (auto finished = movie->finish(); !finished) {
        return finished.error();
    }
    return ExportFile{std::make_shared<const std::vector<std::uint8_t>>(movie->take_bytes()),
                      job.status.file_name, "video/mp4"};
}

void Exporter::run(const std::shared_ptr<Job>& job) {
    const auto make = [&](int tile_side) {
        return job->movie ? make_movie(job, tile_side) : make_still(job, tile_side);
    };
    int side = job->max_tile_side;
    auto file = make(side);
    // Smaller tiles where one asked for more work than a frame may (a fine step, the reference).
    while (!file && file.error().code == base::ErrorCode::too_much_work &&
           side / 2 >= kSmallestTile) {
        side /= 2;
        file = make(side);
    }
    ExportStatus status = job->status;
    if (job->cancelled) {
        status.state = ExportState::cancelled;
        finish(*job, std::move(status));
        return;
    }
    if (!file) {
        status.state = ExportState::failed;
        status.error = file.error();
        finish(*job, std::move(status));
        return;
    }
    status.bytes = file->bytes->size();
    keep(status.id, std::move(file.value()));
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
