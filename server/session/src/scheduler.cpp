#include "penumbra/session/scheduler.hpp"

#include <penumbra/base/log.hpp>
#include <penumbra/encode/encode.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <algorithm>
#include <future>
#include <optional>

namespace penumbra::session {
namespace {

// The protocol's JPEG quality is the scale encode writes at.
static_assert(scene::setting::jpeg_quality.min == encode::kMinJpegQuality &&
              scene::setting::jpeg_quality.max == encode::kMaxJpegQuality);

// A frame through its session's stream; where the job carries none (a job made by hand), a
// stream of this one frame.
base::Result<encode::StreamFrame> encode_frame(const base::ImageRgba8& image,
                                               const scene::Output& output, SessionStream* stream,
                                               bool final_still) {
    if (stream != nullptr) {
        return stream->encode(image, output, final_still);
    }
    scene::Output alone_output = output;
    alone_output.format = frame_format(output, final_still);
    auto alone = encode::make_stream(stream_options(alone_output));
    if (!alone) {
        return alone.error();
    }
    return (*alone)->encode(image, true);
}

double milliseconds_between(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

}  // namespace

std::string_view light_buffer_name(const EncodedFrame& frame) {
    return render::to_string(frame.report.light_buffer);
}

Scheduler::Scheduler(SchedulerOptions options, metrics::Registry& metrics)
    : options_(options)
    , frames_(metrics.counter("penumbra_frames_total", "Frames rendered and encoded"))
    , refinement_frames_(metrics.counter("penumbra_refinement_frames_total",
                                         "Refinement steps of still frames rendered and encoded"))
    , superseded_(metrics.counter("penumbra_frames_superseded_total",
                                  "Render requests replaced by a newer one before rendering"))
    , failures_(metrics.counter("penumbra_render_failures_total", "Render requests that failed"))
    , light_buffer_built_(metrics.counter("penumbra_light_buffer_builds_total",
                                          "Frames that built the light attenuation buffer"))
    , light_buffer_reused_(metrics.counter("penumbra_light_buffer_reuses_total",
                                           "Frames that reused a cached light buffer"))
    , queue_depth_(metrics.gauge("penumbra_render_queue_depth",
                                 "Sessions waiting for the render thread"))
    , gpu_bytes_(metrics.gauge("penumbra_gpu_bytes_held",
                               "GPU memory held by cached volumes and light buffers"))
    , render_ms_(metrics.histogram("penumbra_render_ms", "Render wall time per frame (ms)",
                                   metrics::latency_buckets_ms()))
    , encode_ms_(metrics.histogram("penumbra_encode_ms", "Encode time per frame (ms)",
                                   metrics::latency_buckets_ms()))
    , queued_ms_(metrics.histogram("penumbra_queued_ms",
                                   "Time a request waited for the render thread (ms)",
                                   metrics::latency_buckets_ms())) {}

base::Result<std::unique_ptr<Scheduler>> Scheduler::create(RendererFactory factory,
                                                           SchedulerOptions options,
                                                           metrics::Registry& metrics) {
    std::unique_ptr<Scheduler> scheduler(new Scheduler(options, metrics));
    std::promise<base::Status> ready;
    auto started = ready.get_future();
    scheduler->render_thread_ =
            std::thread([s = scheduler.get(), f = std::move(factory),
                         r = std::move(ready)]() mutable { s->render_loop(f, r); });
    auto status = started.get();
    if (!status) {
        scheduler->render_thread_.join();
        return status.error();
    }
    for (int i = 0; i < std::max(1, options.encode_threads); ++i) {
        scheduler->encode_threads_.emplace_back([s = scheduler.get()] { s->encode_loop(); });
    }
    return scheduler;
}

Scheduler::~Scheduler() {
    stop();
}

void Scheduler::stop() {
    std::map<std::string, Pending> dropped;
    {
        const std::lock_guard lock(mutex_);
        if (stopping_ && !render_thread_.joinable()) {
            return;
        }
        stopping_ = true;
        dropped.swap(pending_);
        clients_.clear();
        sessions_of_.clear();
        refinements_.clear();
        refinement_order_.clear();
    }
    work_ready_.notify_all();
    for (auto& [session, pending] : dropped) {
        pending.done(Withdrawn::shutting_down);
    }
    if (render_thread_.joinable()) {
        render_thread_.join();
    }
    {
        const std::lock_guard lock(encode_mutex_);
        encode_stopping_ = true;
    }
    encode_ready_.notify_all();
    for (auto& thread : encode_threads_) {
        thread.join();
    }
    encode_threads_.clear();
}

void Scheduler::submit(const std::string& session, RenderJob job, FrameCallback done) {
    FrameCallback replaced;
    {
        const std::lock_guard lock(mutex_);
        if (stopping_) {
            done(Withdrawn::shutting_down);
            return;
        }
        if (in_flight_.session == session) {
            in_flight_.superseded = true;
        }
        for (InFlight& submitted : submitted_) {
            submitted.superseded = submitted.superseded || submitted.session == session;
        }
        drop_refinement(session);  // the view it refines is about to change
        const auto found = pending_.find(session);
        if (found != pending_.end()) {
            replaced = std::move(found->second.done);
        }
        if (found != pending_.end() && found->second.job.client == job.client) {
            found->second = Pending{std::move(job), std::move(done)};
        } else {
            if (found != pending_.end()) {
                // Another viewer's request: the session now waits in that client's turn.
                unqueue(session, found->second.job.client);
                pending_.erase(found);
            }
            enqueue(session, Pending{std::move(job), std::move(done)});
        }
    }
    if (replaced) {
        superseded_.add();
        replaced(Withdrawn::superseded);
    }
    work_ready_.notify_one();
}

void Scheduler::submit_background(const std::string& key, RenderJob job, FrameCallback done) {
    job.refinement_steps = 0;
    job.refinement_step = 0;
    job.preview.reset();
    {
        const std::lock_guard lock(mutex_);
        if (stopping_) {
            done(Withdrawn::shutting_down);
            return;
        }
        queue_refinement(key, std::move(job), std::move(done));
    }
    work_ready_.notify_one();
}

void Scheduler::cancel(const std::string& session) {
    FrameCallback dropped;
    {
        const std::lock_guard lock(mutex_);
        if (in_flight_.session == session) {
            in_flight_.closed = true;
        }
        for (InFlight& submitted : submitted_) {
            submitted.closed = submitted.closed || submitted.session == session;
        }
        drop_refinement(session);
        auto found = pending_.find(session);
        if (found == pending_.end()) {
            return;
        }
        dropped = std::move(found->second.done);
        unqueue(session, found->second.job.client);
        pending_.erase(found);
        queue_depth_.set(static_cast<double>(pending_.size()));
    }
    superseded_.add();
    dropped(Withdrawn::superseded);
}

void Scheduler::enqueue(const std::string& session, Pending pending) {
    const std::string client = pending.job.client;
    pending_.emplace(session, std::move(pending));
    auto& sessions = sessions_of_[client];
    if (sessions.empty()) {
        clients_.push_back(client);
    }
    sessions.push_back(session);
    queue_depth_.set(static_cast<double>(pending_.size()));
}

void Scheduler::queue_still_after_preview(const InFlight& preview, RenderJob job,
                                          FrameCallback done) {
    if (stopping_ || preview.closed || preview.superseded || pending_.contains(preview.session)) {
        return;  // a newer job replaces the view, or nobody is left to see it
    }
    job.submitted = Clock::now();
    enqueue(preview.session, Pending{std::move(job), std::move(done)});
}

void Scheduler::unqueue(const std::string& session, const std::string& client) {
    const auto sessions = sessions_of_.find(client);
    if (sessions == sessions_of_.end()) {
        return;
    }
    std::erase(sessions->second, session);
    if (sessions->second.empty()) {
        sessions_of_.erase(sessions);
        std::erase(clients_, client);
    }
}

void Scheduler::queue_refinement(const std::string& session, RenderJob job, FrameCallback done) {
    if (stopping_ || pending_.contains(session)) {
        return;  // a newer job replaces the view this step would refine
    }
    job.submitted = Clock::now();
    if (!refinements_.contains(session)) {
        refinement_order_.push_back(session);
    }
    refinements_.insert_or_assign(session, Pending{std::move(job), std::move(done)});
}

void Scheduler::drop_refinement(const std::string& session) {
    if (refinements_.erase(session) > 0) {
        std::erase(refinement_order_, session);
    }
}

bool Scheduler::take_refinement(Pending& next) {
    if (!clients_.empty() || refinement_order_.empty()) {
        return false;
    }
    const std::string session = refinement_order_.front();
    refinement_order_.pop_front();
    auto found = refinements_.find(session);
    next = std::move(found->second);
    refinements_.erase(found);
    in_flight_ = {session, Clock::now()};
    in_flight_.refinement = true;
    return true;
}

std::size_t Scheduler::queue_depth() const {
    const std::lock_guard lock(mutex_);
    return pending_.size();
}

Device Scheduler::device() const {
    const render::RendererInfo& info = renderer_info_;
    return {.renderer = info.renderer,
            .version = info.version,
            .platform = info.platform,
            .software = info.software,
            .max_texture_size = info.max_texture_size,
            .max_array_texture_layers = info.max_array_texture_layers};
}

SchedulerCounts Scheduler::counts() const {
    return {frames_.value(), light_buffer_built_.value(), light_buffer_reused_.value(),
            gpu_bytes_.value()};
}

void Scheduler::render_loop(const RendererFactory& factory, std::promise<base::Status>& ready) {
    auto created = factory();
    if (!created) {
        ready.set_value(created.error());
        return;
    }
    std::unique_ptr<render::FrameRenderer> renderer = std::move(created.value());
    renderer_info_ = renderer->info();
    ready.set_value(base::Ok{});
    const int depth = std::clamp(options_.frames_in_flight > 0 ? options_.frames_in_flight
                                                               : renderer_info_.frames_in_flight,
                                 1, 4);
    std::deque<Submitted> submitted;  // oldest first
    while (true) {
        Pending next;
        bool taken = false;
        {
            std::unique_lock lock(mutex_);
            if (submitted.empty()) {
                work_ready_.wait(lock, [&] {
                    return stopping_ || !clients_.empty() || !refinement_order_.empty();
                });
            }
            if (stopping_) {
                break;
            }
            taken = std::ssize(submitted) < depth && take_next(next);
        }
        if (taken) {
            if (auto job = submit_one(*renderer, std::move(next.job), std::move(next.done))) {
                submitted.push_back(std::move(*job));
            }
            continue;
        }
        // Nothing more to submit now: wait for the oldest frame.
        complete_one(*renderer, std::move(submitted.front()));
        submitted.pop_front();
    }
    while (!submitted.empty()) {
        complete_one(*renderer, std::move(submitted.front()));
        submitted.pop_front();
    }
    // The renderer (and its GL context) is destroyed on the thread that created it.
    renderer.reset();
}

bool Scheduler::take_next(Pending& next) {
    // Nothing else waits: the next session's refinement step, at the lowest priority.
    if (take_refinement(next)) {
        return true;
    }
    if (clients_.empty()) {
        return false;
    }
    // The client whose turn it is, then that client's session whose turn it is; both go to the
    // back of their queues.
    const std::string client = clients_.front();
    clients_.pop_front();
    auto& sessions = sessions_of_.at(client);
    const std::string session = sessions.front();
    sessions.pop_front();
    if (sessions.empty()) {
        sessions_of_.erase(client);
    } else {
        clients_.push_back(client);
    }
    auto found = pending_.find(session);
    next = std::move(found->second);
    pending_.erase(found);
    queue_depth_.set(static_cast<double>(pending_.size()));
    in_flight_ = {session, Clock::now()};
    return true;
}

void Scheduler::queue_in_order(const std::string& session, std::function<void()> task) {
    {
        const std::lock_guard lock(encode_mutex_);
        encode_queue_.push_back({session, std::move(task)});
    }
    encode_ready_.notify_one();
}

void Scheduler::deliver_in_order(const std::string& session, FrameCallback done,
                                 FrameOutcome outcome) {
    queue_in_order(session, [done = std::move(done), outcome = std::move(outcome)]() mutable {
        done(std::move(outcome));
    });
}

std::optional<Scheduler::Submitted> Scheduler::submit_one(render::FrameRenderer& renderer,
                                                          RenderJob job, FrameCallback done) {
    const double queued_ms = milliseconds_between(job.submitted, Clock::now());
    queued_ms_.observe(queued_ms);
    std::string session;
    {
        const std::lock_guard lock(mutex_);
        session = in_flight_.session;
    }
    // A preview is rendered in the still's place; the still follows it.
    std::optional<RenderJob> still_after_preview;
    if (job.preview) {
        RenderJob preview = job;
        preview.request = std::move(job.preview->request);
        preview.quality = std::move(job.preview->quality);
        preview.preview.reset();
        job.preview.reset();
        still_after_preview = std::move(job);
        job = std::move(preview);
    }
    Submitted submitted{.session = session,
                        .job = std::move(job),
                        .done = std::move(done),
                        .frame = std::nullopt,
                        .outcome = std::nullopt,
                        .still_after_preview = std::move(still_after_preview),
                        .queued_ms = queued_ms};
    const RenderJob& taken = submitted.job;
    auto result = [&]() -> base::Result<render::SubmittedFrame> {
        if (auto status = renderer.set_volume(taken.volume); !status) {
            return status.error();
        }
        if (auto status = renderer.set_labels(taken.labels); !status) {
            return status.error();
        }
        return renderer.submit(taken.request, [this] { return in_flight_cancelled(); });
    }();
    gpu_bytes_.set(static_cast<double>(renderer.gpu_bytes_held()));
    const std::lock_guard lock(mutex_);
    const InFlight in_flight = std::exchange(in_flight_, {});
    if (!result && result.error().code == base::ErrorCode::cancelled && in_flight.refinement &&
        !in_flight.closed && !stopping_) {
        // Preempted by another job: a job of the lowest priority waits for its next turn,
        // unchanged.
        queue_refinement(session, std::move(submitted.job), std::move(submitted.done));
        return std::nullopt;
    }
    if (taken.refinement_step > 0 && !result) {
        if (result.error().code != base::ErrorCode::cancelled) {
            // The still frame stands; only its refinement ends.
            base::log_warning("session", "refinement of session " + session +
                                                 " stopped: " + result.error().to_string());
        }
        return std::nullopt;
    }
    if (result) {
        submitted.frame = std::move(result.value());
    } else if (result.error().code == base::ErrorCode::cancelled) {
        if (!stopping_) {
            superseded_.add();
        }
        submitted.outcome = stopping_ ? Withdrawn::shutting_down : Withdrawn::superseded;
    } else {
        failures_.add();
        submitted.outcome = FrameFailure{result.error(), taken.request_id};
    }
    submitted_.push_back(in_flight);
    return submitted;
}

void Scheduler::complete_one(render::FrameRenderer& renderer, Submitted submitted) {
    std::optional<base::Result<render::Frame>> rendered;
    if (submitted.frame) {
        rendered = renderer.complete(std::move(*submitted.frame));
    }
    gpu_bytes_.set(static_cast<double>(renderer.gpu_bytes_held()));
    const std::string& session = submitted.session;
    RenderJob& job = submitted.job;
    const int step = job.refinement_step;
    // The frame, before its fate is known: what follows it is decided under the same lock that
    // takes its record, so that a cancel() can never slip in between.
    std::shared_ptr<EncodedFrame> frame;
    std::shared_ptr<const base::ImageRgba8> image;
    if (rendered && *rendered) {
        render::Frame& result = rendered->value();
        frame = std::make_shared<EncodedFrame>();
        frame->report = std::move(result.report);
        frame->width = result.image.width;
        frame->height = result.image.height;
        frame->format = job.output.format;
        frame->mode = job.request.settings.mode;
        frame->sample_distance = job.request.settings.sample_distance;
        frame->request_id = job.request_id;
        frame->interactive = job.interactive;
        frame->quality = job.quality;
        frame->refinement_step = step;
        frame->preview = submitted.still_after_preview.has_value();
        frame->refining = frame->preview;  // the still follows it
        frame->queued_ms = submitted.queued_ms;
        for (const auto& pass : frame->report.passes) {
            if (pass.name == "readback") {
                frame->readback_ms += pass.wall_ms;
            } else {
                frame->render_ms += pass.wall_ms;
            }
        }
        image = std::make_shared<const base::ImageRgba8>(std::move(result.image));
        if (!job.interactive && !submitted.still_after_preview && step < job.refinement_steps) {
            std::optional<double> change;
            if (job.refined_image) {
                if (auto measured = base::change_in_levels(*job.refined_image, *image)) {
                    change = *measured;
                }
            }
            frame->refining = scene::refines_after(step, change, job.refinement_steps,
                                                   job.refinement_threshold);
        }
    }
    bool stopping = false;
    InFlight record;
    {
        const std::lock_guard lock(mutex_);
        record = std::move(submitted_.front());
        submitted_.pop_front();
        stopping = stopping_;
        if (frame && !stopping && !record.closed) {
            if (submitted.still_after_preview) {
                queue_still_after_preview(record, std::move(*submitted.still_after_preview),
                                          submitted.done);
            } else if (frame->refining && !record.superseded) {
                RenderJob next = job;
                next.refinement_step = step + 1;
                if (step == 0) {
                    next.request = scene::refinement_step_request(job.request, 1);
                } else {
                    next.request.refinement = {false, step};
                }
                next.refined_image = image;
                queue_refinement(session, std::move(next), submitted.done);
            }
        }
    }
    if (submitted.outcome) {
        deliver_in_order(session, std::move(submitted.done), std::move(*submitted.outcome));
        return;
    }
    if (stopping || record.closed) {
        // Rendered, but nobody is left to see it. A refinement step hands on its frame only.
        if (step == 0) {
            if (!stopping) {
                superseded_.add();
            }
            deliver_in_order(session, std::move(submitted.done),
                             stopping ? Withdrawn::shutting_down : Withdrawn::superseded);
        }
        return;
    }
    if (!frame) {
        if (step > 0) {
            // The still frame stands; only its refinement ends.
            base::log_warning("session", "refinement of session " + session +
                                                 " stopped: " + rendered->error().to_string());
            return;
        }
        failures_.add();
        deliver_in_order(session, std::move(submitted.done),
                         FrameFailure{rendered->error(), job.request_id});
        return;
    }
    render_ms_.observe(frame->render_ms);
    if (frame->report.light_buffer == render::LightBufferState::built) {
        light_buffer_built_.add();
    } else if (frame->report.light_buffer == render::LightBufferState::reused) {
        light_buffer_reused_.add();
    }
    if (job.raw) {
        frame->pixels = image;
        frames_.add();
        queue_in_order(session, [frame, done = std::move(submitted.done)]() mutable {
            done(std::shared_ptr<const EncodedFrame>(std::move(frame)));
        });
        return;
    }
    const bool final_still = !frame->interactive && !frame->refining && !frame->preview;
    frame->format = frame_format(job.output, final_still);
    queue_in_order(session, [this, frame, image, output = job.output, stream = job.stream,
                             final_still, done = std::move(submitted.done)]() mutable {
        const Clock::time_point start = Clock::now();
        auto encoded = encode_frame(*image, output, stream.get(), final_still);
        if (!encoded) {
            failures_.add();
            done(FrameFailure{encoded.error(), frame->request_id});
            return;
        }
        frame->image = std::move(encoded->bytes);
        frame->independent = encoded->independent;
        frame->encode_ms = milliseconds_between(start, Clock::now());
        encode_ms_.observe(frame->encode_ms);
        frames_.add();
        if (frame->refinement_step > 0) {
            refinement_frames_.add();
        }
        done(std::shared_ptr<const EncodedFrame>(std::move(frame)));
    });
}

bool Scheduler::in_flight_cancelled() const {
    const std::lock_guard lock(mutex_);
    return stopping_ || in_flight_.closed || (in_flight_.refinement && !clients_.empty()) ||
           (in_flight_.superseded &&
            Clock::now() - in_flight_.started >= options_.supersede_running_after);
}

void Scheduler::encode_loop() {
    while (true) {
        EncodeTask task;
        {
            std::unique_lock lock(encode_mutex_);
            // The oldest frame of a session that no other thread is encoding now.
            auto next = encode_queue_.end();
            encode_ready_.wait(lock, [&] {
                next = std::find_if(encode_queue_.begin(), encode_queue_.end(),
                                    [&](const EncodeTask& queued) {
                                        return !sessions_encoding_.contains(queued.session);
                                    });
                return next != encode_queue_.end() || (encode_stopping_ && encode_queue_.empty());
            });
            if (next == encode_queue_.end()) {
                return;  // stopping, and everything queued has been encoded
            }
            task = std::move(*next);
            encode_queue_.erase(next);
            sessions_encoding_.insert(task.session);
        }
        task.run();
        {
            const std::lock_guard lock(encode_mutex_);
            sessions_encoding_.erase(task.session);
        }
        encode_ready_.notify_all();
    }
}

}  // namespace penumbra::session
