#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/metrics/registry.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/session/session_stream.hpp>
#include <penumbra/volume/volume.hpp>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <thread>
#include <variant>
#include <vector>

namespace penumbra::session {

using Clock = std::chrono::steady_clock;

struct RenderJob {
    std::shared_ptr<const volume::Volume> volume;
    // The label map the request's labels style (null when it styles none).
    std::shared_ptr<const volume::LabelMap> labels;
    scene::FrameRequest request;
    scene::Output output;
    // The session's stream, which encodes its frames in order (null: each frame alone).
    std::shared_ptr<SessionStream> stream;
    std::int64_t request_id = -1;  // the id of the request that asked for the frame; -1: none
    bool interactive = false;
    std::string quality;  // how the request was reduced, for the frame header
    Clock::time_point submitted = Clock::now();
    // Who asked (a remote address): render time is shared among clients first, then among the
    // sessions of each client, so opening many sessions buys a client no larger share.
    std::string client;
    // Progressive stills: after this still frame the scheduler renders up to this many refinement
    // steps of it at the lowest priority, delivering each through the same callback, and stops
    // sooner once a step changes the image by no more than `refinement_threshold`
    // (scene::refines_after).
    int refinement_steps = 0;
    double refinement_threshold = 0.0;
    // Which frame of the still this is: 0 the still itself, k its k-th refinement step, whose
    // request scene::refinement_step_request made (a finer step, averaged from step 1 on).
    int refinement_step = 0;
    // A refinement step's: the image the step before it delivered, which its change is measured
    // against.
    std::shared_ptr<const base::ImageRgba8> refined_image;

    // A still expected to take longer than its budget (scene::still_preview) is first rendered
    // as this smaller frame; the still itself (`request`, `quality`) follows in its client's turn,
    // as any job does, then its own refinement steps.
    struct Preview {
        scene::FrameRequest request;
        std::string quality;
    };

    std::optional<Preview> preview;

    // The frame's pixels are handed on as they are (EncodedFrame::pixels), not encoded: a tile of
    // an export, which the exporter puts together with the others.
    bool raw = false;
};

struct EncodedFrame {
    std::vector<std::uint8_t> image;  // JPEG or PNG bytes, or an H.264 access unit
    // RenderJob::raw: the frame's pixels instead of `image`.
    std::shared_ptr<const base::ImageRgba8> pixels;
    int width = 0;
    int height = 0;
    scene::FrameFormat format = scene::FrameFormat::jpeg;
    // Decodable without the frames before it (every JPEG or PNG frame; an H.264 keyframe).
    bool independent = true;
    scene::Mode mode = scene::Mode::dvr;
    double sample_distance = 0.0;  // the request's: a ray's samples, so its cost, go as 1 / it
    render::FrameReport report;
    std::int64_t request_id = -1;
    bool interactive = false;
    std::string quality;
    int refinement_step = 0;  // 0: a frame on its own; k: the still frame refined k times
    // Another refinement step of this still follows (unless a newer frame replaces the view).
    bool refining = false;
    // A still's smaller first frame (RenderJob::preview): the still at full size follows.
    bool preview = false;
    double queued_ms = 0.0;  // submitted -> the render thread took it
    double render_ms = 0.0;  // GPU passes, wall time
    double readback_ms = 0.0;
    double encode_ms = 0.0;
};

// The name a frame header gives what became of the frame's light buffer ("none", "built",
// "reused").
[[nodiscard]] std::string_view light_buffer_name(const EncodedFrame& frame);

// Why a job ended without a frame although nothing failed; nobody needs to hear of it.
enum class Withdrawn {
    superseded,     // a newer job of its session replaced it, or its session was closed
    shutting_down,  // the scheduler stopped
};

// Why a job's rendering or encoding failed, and the request that asked for the frame, so that
// the failure answers that request as its frame would have.
struct FrameFailure {
    base::Error error;
    std::int64_t request_id = -1;  // the job's RenderJob::request_id
};

// How a job ended: with its frame, withdrawn, or failed.
using FrameOutcome = std::variant<std::shared_ptr<const EncodedFrame>, Withdrawn, FrameFailure>;

// Called once per submitted job, then once more per refinement step of a still frame
// (RenderJob::refinement_steps) with the refined frame only; on a scheduler thread: it must only
// hand the outcome on.
using FrameCallback = std::function<void(FrameOutcome outcome)>;

// What the scheduler has done since it started, for `stats`.
struct SchedulerCounts {
    std::uint64_t frames = 0;
    std::uint64_t light_buffer_builds = 0;
    std::uint64_t light_buffer_reuses = 0;
    double gpu_bytes_held = 0;
};

// The device the scheduler renders on, as a server describes it to its clients and bounds what it
// accepts by: the GL's names, and the largest texture side and number of array layers it can
// allocate.
struct Device {
    std::string renderer;   // GL_RENDERER
    std::string version;    // GL_VERSION
    std::string platform;   // EGL's platform
    bool software = false;  // a software rasteriser (llvmpipe): no GPU
    int max_texture_size = 0;
    int max_array_texture_layers = 0;
};

struct SchedulerOptions {
    int encode_threads = 2;
    // A newer request of the session whose frame is rendering cancels that frame once it has
    // rendered this long (between two of its chunks): a long frame yields the render thread to
    // the newer request, a short one finishes, so a session that asks faster than its frames
    // render still sees frames.
    std::chrono::milliseconds supersede_running_after{500};
    // Frames submitted to the renderer before the render thread waits for the oldest of them
    // (render::FrameRenderer::submit), 1 to 4; 0: the device's (RendererInfo::frames_in_flight).
    int frames_in_flight = 0;
};

// One render thread owns the renderer (and so the GL context) for all sessions. Each session
// has at most one pending job: a newer one replaces an unrendered older one (latest wins).
// Clients with pending jobs are served round-robin, and the sessions of one client round-robin
// in turn, so neither a busy session nor a client with many sessions can starve others.
// The frame being rendered is cancelled between its chunks when its session is closed, when the
// scheduler stops, and when a newer request of its session has waited for it long enough
// (SchedulerOptions::supersede_running_after). On a GPU the render thread submits the next
// frame before it waits for the one before (SchedulerOptions::frames_in_flight), so that the GPU
// draws one while the CPU issues the other; frames are completed, and their outcomes handed on,
// in the order they were taken. Encoding runs on a pool of worker threads, overlapping the next
// render.
class Scheduler {
public:
    using RendererFactory = std::function<base::Result<std::unique_ptr<render::FrameRenderer>>()>;

    // Creates the renderer on the render thread and waits for it; fails if it cannot be created.
    static base::Result<std::unique_ptr<Scheduler>> create(RendererFactory factory,
                                                           SchedulerOptions options,
                                                           metrics::Registry& metrics);

    Scheduler(const Scheduler&) = delete;
    Scheduler& operator=(const Scheduler&) = delete;
    ~Scheduler();

    void submit(const std::string& session, RenderJob job, FrameCallback done);

    // Queues `job` at the lowest priority, beside progressive stills' refinement steps: rendered
    // only while no client has a job waiting, preempted between its chunks by any that comes (and
    // then rendered again in its next turn). `key` names it as a session does its jobs (cancel);
    // one job per key waits at a time, a newer replacing it. For work that no one watches frame by
    // frame: an export's tiles. Its refinement steps, if it asks for any, are not rendered.
    void submit_background(const std::string& key, RenderJob job, FrameCallback done);

    // Drops the session's pending job, if any, and cancels its frame in flight (both end
    // Withdrawn::superseded); a job of submit_background's `key` the same way, except that one
    // waiting for its turn is dropped without a word to its callback.
    void cancel(const std::string& session);

    [[nodiscard]] const render::RendererInfo& renderer_info() const { return renderer_info_; }

    [[nodiscard]] Device device() const;

    [[nodiscard]] std::size_t queue_depth() const;

    [[nodiscard]] SchedulerCounts counts() const;

    // Stops accepting work, drops pending jobs, cancels the frame in flight, finishes the
    // encodes.
    void stop();

private:
    Scheduler(SchedulerOptions options, metrics::Registry& metrics);

    struct Pending {
        RenderJob job;
        FrameCallback done;
    };

    // A job the render thread took, between submit_one and complete_one: its frame in flight on
    // the renderer, or the outcome it already had (a failure, a withdrawal), which waits here so
    // that it reaches the client after the frames taken before it.
    struct Submitted {
        std::string session;
        RenderJob job;
        FrameCallback done;
        std::optional<render::SubmittedFrame> frame;
        std::optional<FrameOutcome> outcome;
        // A preview's: the still that follows it once it is complete.
        std::optional<RenderJob> still_after_preview;
        double queued_ms = 0.0;
    };

    void render_loop(const RendererFactory& factory, std::promise<base::Status>& ready);
    void encode_loop();
    // Takes the next job to render into `next` and marks it in flight: a client's in its turn,
    // or with none waiting a refinement step (under mutex_).
    bool take_next(Pending& next);
    // Sets up and submits the job in flight; nothing when there is nothing to hand on (a
    // refinement step preempted or stopped).
    std::optional<Submitted> submit_one(render::FrameRenderer& renderer, RenderJob job,
                                        FrameCallback done);
    // Waits for the oldest submitted frame and queues its encode, its refinement step or the still
    // after it.
    void complete_one(render::FrameRenderer& renderer, Submitted submitted);
    // Whether the frame in flight should stop; asked by the renderer between chunks.
    bool in_flight_cancelled() const;

    // Takes `session` out of its client's turn (under mutex_).
    void unqueue(const std::string& session, const std::string& client);

    // Puts the session's job in its client's turn; the session has none pending (under mutex_).
    void enqueue(const std::string& session, Pending pending);

    struct InFlight;

    // Queues the still that follows its preview (`preview`) in its client's turn, as any job of
    // the session, unless the session was closed or superseded meanwhile (under mutex_).
    void queue_still_after_preview(const InFlight& preview, RenderJob job, FrameCallback done);

    // Queues the refinement step that follows `job` at the lowest priority (under mutex_).
    void queue_refinement(const std::string& session, RenderJob job, FrameCallback done);

    // Drops the session's queued refinement step, if any (under mutex_).
    void drop_refinement(const std::string& session);

    // Takes the next refinement step into `next` and marks it in flight, when no client has a
    // job pending (under mutex_).
    bool take_refinement(Pending& next);

    // Queues `task` (an encode, or handing an outcome on) behind the session's tasks already
    // queued; encoder threads run one task of a session at a time, in order (takes encode_mutex_).
    void queue_in_order(const std::string& session, std::function<void()> task);

    // Hands an outcome that is no frame (a failure, a withdrawal) to `done` after every frame of
    // `session` already waiting for an encoder, as their requests came: a still that fails after
    // its preview must not reach the client before the preview does (takes encode_mutex_).
    void deliver_in_order(const std::string& session, FrameCallback done, FrameOutcome outcome);

    SchedulerOptions options_;
    render::RendererInfo renderer_info_;
    mutable std::mutex mutex_;
    std::condition_variable work_ready_;
    std::map<std::string, Pending> pending_;  // by session
    std::deque<std::string> clients_;         // clients with a pending job, in serving order
    std::map<std::string, std::deque<std::string>> sessions_of_;  // a client's sessions, in order
    bool stopping_ = false;
    // Progressive stills: each session's next refinement step, served in turn and only while no
    // client has a job pending. A job of any session preempts a refinement step between its
    // chunks, which then waits for its next turn.
    std::map<std::string, Pending> refinements_;
    std::deque<std::string> refinement_order_;

    // A job on the render thread (guarded by mutex_), so that others can cancel it.
    struct InFlight {
        std::string session;  // empty while the render thread is idle
        Clock::time_point started;
        bool superseded = false;  // a newer job of the session came
        bool closed = false;      // the session was cancelled
        bool refinement = false;  // a refinement step, which yields to any pending job
    };

    InFlight in_flight_;  // the job being submitted
    // The jobs submitted and not yet completed, oldest first (the render thread's Submitted).
    std::deque<InFlight> submitted_;

    // Encoding runs on several threads, but one session's frames are encoded one at a time, in
    // the order they were rendered, so that its viewers get them in that order (a refinement
    // step never before the still frame it refines).
    struct EncodeTask {
        std::string session;
        std::function<void()> run;
    };

    std::mutex encode_mutex_;
    std::condition_variable encode_ready_;
    std::deque<EncodeTask> encode_queue_;
    std::set<std::string> sessions_encoding_;
    bool encode_stopping_ = false;

    std::thread render_thread_;
    std::vector<std::thread> encode_threads_;

    metrics::Counter& frames_;
    metrics::Counter& refinement_frames_;
    metrics::Counter& superseded_;
    metrics::Counter& failures_;
    metrics::Counter& light_buffer_built_;
    metrics::Counter& light_buffer_reused_;
    metrics::Gauge& queue_depth_;
    metrics::Gauge& gpu_bytes_;
    metrics::Histogram& render_ms_;
    metrics::Histogram& encode_ms_;
    metrics::Histogram& queued_ms_;
};

}  // namespace penumbra::session
