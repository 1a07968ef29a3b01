#include "connection_handler.hpp"

#include <penumbra/base/assert.hpp>
#include <penumbra/base/log.hpp>
#include <penumbra/protocol/frame_header.hpp>
#include <penumbra/protocol/scene_json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>

namespace penumbra::net {
namespace {

using Clock = std::chrono::steady_clock;

// An export's status as the wire carries it; a finished one's URL is its download's
// (http_session.cpp).
protocol::ExportSummary export_summary(const session::ExportStatus& status) {
    protocol::ExportSummary summary;
    summary.export_id = status.id;
    summary.state = session::to_string(status.state);
    summary.progress = status.progress;
    summary.width = status.width;
    summary.height = status.height;
    summary.tiles = status.tiles;
    summary.frames = status.frames;
    summary.bytes = status.bytes;
    if (status.state == session::ExportState::done) {
        summary.url = std::string(kExportsPath) + status.id;
    }
    if (status.state == session::ExportState::failed && status.error) {
        // As a frame's failure reaches its client: a code of the wire's, else render_failed
        // saying what went wrong.
        base::Error error = *status.error;
        if (std::ranges::find(protocol::kWireCodes, error.code) == protocol::kWireCodes.end()) {
            error = base::make_error(base::ErrorCode::render_failed, error.to_string(), "export");
        }
        summary.error = std::move(error);
    }
    return summary;
}

// A flooding client's refused requests are answered from an allowance of their own: this many at
// once, refilled at the request rate. So a flood gets a bounded number of error replies per
// second however fast or slowly the server reads it; the rest are refused without a reply.
constexpr double max_refusal_replies = 64.0;

// Requests that may wait while a volume loads for this connection; more are refused.
constexpr std::size_t max_waiting_requests = 64;

protocol::VolumeSummary summary_of(const session::VolumeSummary& v) {
    protocol::VolumeSummary out;
    out.id = v.id;
    out.name = v.name;
    out.loaded = v.loaded;
    out.label_map = v.label_map;
    if (v.loaded) {
        out.dims[0] = v.dims.x;
        out.dims[1] = v.dims.y;
        out.dims[2] = v.dims.z;
        out.spacing[0] = v.spacing.x;
        out.spacing[1] = v.spacing.y;
        out.spacing[2] = v.spacing.z;
        out.voxel_type = v.voxel_type;
        out.range[0] = v.min;
        out.range[1] = v.max;
        out.hounsfield = v.hounsfield;
        for (int axis = 0; axis < 3; ++axis) {
            out.bounds[0][axis] = v.bounds.min[axis];
            out.bounds[1][axis] = v.bounds.max[axis];
        }
    }
    return out;
}

// What a new session of this server on `volume` starts from: a CT's own preset for a CT.
scene::State initial_state(const ServerConfig& config, const session::LoadedVolume& volume) {
    return session::default_state((*volume)->hounsfield ? config.default_ct_transfer_function
                                                        : config.default_transfer_function,
                                  protocol::scene_limits(config.limits));
}

std::vector<std::uint8_t> pack(const session::SharedFrame& shared) {
    const session::EncodedFrame& f = shared.frame();
    protocol::FrameHeader h;
    h.frame = shared.number();
    h.request = f.request_id;
    h.session = shared.session();
    h.width = f.width;
    h.height = f.height;
    h.encoding = scene::to_string(f.format);
    h.independent = f.independent;
    h.mode = scene::to_string(f.mode);
    h.interactive = f.interactive;
    h.light_buffer = session::light_buffer_name(f);
    for (const auto& pass : f.report.passes) {
        h.passes.push_back({pass.name, pass.gpu_ms, pass.wall_ms});
    }
    h.queued_ms = f.queued_ms;
    h.render_ms = f.render_ms;
    h.readback_ms = f.readback_ms;
    h.encode_ms = f.encode_ms;
    h.quality = f.quality;
    h.refinement = f.refinement_step;
    h.refining = f.refining;
    h.preview = f.preview;
    return protocol::pack_frame(h, f.image);
}

}  // namespace

ConnectionHandler::ConnectionHandler(Context& context, std::weak_ptr<Connection> connection,
                                     std::string client)
    : context_(context)
    , connection_(std::move(connection))
    , viewer_(context.next_viewer.fetch_add(1))
    , tokens_(context.config.limits.max_requests_per_second)
    , refusal_tokens_(max_refusal_replies)
    , last_refill_(Clock::now())
    , client_(std::move(client)) {}

void ConnectionHandler::send(std::string text) {
    if (auto connection = connection_.lock()) {
        connection->send_text(std::move(text));
    }
}

void ConnectionHandler::reply_error(std::optional<std::int64_t> id, const base::Error& error) {
    // A client learns where a file is inside the data folder, never where the folder is.
    const session::VolumeStore& volumes = context_.services.volumes;
    send(protocol::error_message(id, base::Error{error.code, volumes.relative_paths(error.message),
                                                 volumes.relative_paths(error.where)}));
    context_.errors.add();
}

bool ConnectionHandler::take_token() {
    const double rate = context_.config.limits.max_requests_per_second;
    const Clock::time_point now = Clock::now();
    const double refill = rate * std::chrono::duration<double>(now - last_refill_).count();
    tokens_ = std::min(rate, tokens_ + refill);
    refusal_tokens_ = std::min(max_refusal_replies, refusal_tokens_ + refill);
    last_refill_ = now;
    if (tokens_ >= 1.0) {
        tokens_ -= 1.0;
        return true;
    }
    return false;
}

void ConnectionHandler::on_open() {
    const session::Device device = context_.services.scheduler.device();
    send(protocol::hello_message(context_.config.limits, {device.renderer, device.version,
                                                          device.platform, device.software}));
}

bool ConnectionHandler::admit(std::optional<std::int64_t> id) {
    context_.messages.add();
    if (take_token()) {
        return true;
    }
    if (refusal_tokens_ < 1.0) {
        return false;
    }
    refusal_tokens_ -= 1.0;
    reply_error(id,
                base::make_error(base::ErrorCode::rate_limited,
                                 "more than " +
                                         std::to_string(static_cast<int>(
                                                 context_.config.limits.max_requests_per_second)) +
                                         " requests per second",
                                 "/"));
    return false;
}

void ConnectionHandler::on_binary() {
    if (!admit(std::nullopt)) {
        return;
    }
    reply_error(std::nullopt, base::make_error(base::ErrorCode::invalid_message,
                                               "clients send text (JSON) messages only", "/"));
}

void ConnectionHandler::on_text(std::string_view text) {
    if (!admit(protocol::request_id_of(text))) {
        return;
    }
    auto request = protocol::parse_request(text, context_.config.limits);
    if (!request) {
        reply_error(text.size() <= context_.config.limits.max_message_bytes
                            ? protocol::request_id_of(text)
                            : std::nullopt,
                    request.error());
        return;
    }
    if (busy_) {
        if (waiting_.size() >= max_waiting_requests) {
            reply_error(request->id,
                        base::make_error(base::ErrorCode::rate_limited,
                                         "too many requests while a volume loads", "/"));
            return;
        }
        waiting_.push_back(std::move(request.value()));
        return;
    }
    handle(*request);
}

namespace {

// `labels` message of the label map a session draws (none: an empty map).
std::string drawn_labels_message(std::optional<std::int64_t> id, const std::string& session,
                                 const session::DrawnLabels& labels, const scene::State& state) {
    std::vector<protocol::LabelSummary> summaries;
    if (labels.map) {
        for (std::size_t i = 0; i < labels.map->labels.size(); ++i) {
            const volume::Label& label = labels.map->labels[i];
            summaries.push_back({label.id,
                                 label.name,
                                 {label.color.r, label.color.g, label.color.b},
                                 labels.map->voxels[i]});
        }
    }
    return protocol::labels_message(id, session, labels.map ? labels.id : std::string{}, summaries,
                                    state);
}

}  // namespace

ConnectionHandler::Sinks ConnectionHandler::sinks_for(const std::string& session_id) {
    std::weak_ptr<Connection> weak = connection_;
    // The session's frames reach this connection from its next keyframe on (the session sends one
    // to a viewer who joins or resumes).
    if (auto connection = weak.lock()) {
        connection->restart_stream();
    }
    Context* context = &context_;
    auto state_changed = [weak, session_id](const scene::State& state,
                                            const session::DrawnLabels* labels) {
        auto connection = weak.lock();
        if (!connection) {
            return;
        }
        if (labels != nullptr) {
            // Not a state a newer one supersedes while it waits: the labels' names go with it.
            connection->send_text(drawn_labels_message(std::nullopt, session_id, *labels, state));
        } else {
            connection->send_state(protocol::state_message(session_id, state));
        }
    };
    auto frames = [weak, context, session_id](const session::ViewerOutcome& outcome) {
        auto connection = weak.lock();
        if (!connection) {
            return;
        }
        if (const auto* failure = std::get_if<session::FrameFailure>(&outcome)) {
            // A frame over the work ceiling is the client's to shrink: a code of its own. The
            // error answers the request that asked for the frame, as the frame would have.
            const base::Error& error = failure->error;
            const bool too_much_work = error.code == base::ErrorCode::too_much_work;
            connection->send_text(protocol::error_message(
                    failure->request_id == -1 ? std::nullopt
                                              : std::optional<std::int64_t>(failure->request_id),
                    base::make_error(too_much_work ? base::ErrorCode::too_much_work
                                                   : base::ErrorCode::render_failed,
                                     context->services.volumes.relative_paths(
                                             too_much_work ? error.message : error.to_string()),
                                     "/")));
            context->errors.add();
            return;
        }
        // Packed by the first viewer's connection, shared by every other one.
        const auto& shared_frame = std::get<std::shared_ptr<const session::SharedFrame>>(outcome);
        connection->send_frame(shared_frame->packed([context](const session::SharedFrame& shared) {
            const session::EncodedFrame& frame = shared.frame();
            context->frame_server_ms.observe(frame.queued_ms + frame.render_ms + frame.readback_ms +
                                             frame.encode_ms);
            return pack(shared);
        }),
                               shared_frame->frame().independent, [context, session_id] {
                                   // This viewer lost a frame of the stream: the session's next is
                                   // a keyframe.
                                   if (auto session = context->services.sessions.find(session_id)) {
                                       session->want_keyframe();
                                   }
                               });
    };
    return {std::move(frames), std::move(state_changed)};
}

void ConnectionHandler::leave_session() {
    if (!session_) {
        return;
    }
    if (context_.services.sessions.leave(*session_, viewer_, context_.services.scheduler)) {
        context_.sessions.set(static_cast<double>(context_.services.sessions.count()));
        base::log_info("session", "closed " + session_->id());
    }
    session_.reset();
}

void ConnectionHandler::on_close() {
    for (const std::string& id : exports_) {
        context_.exporter.cancel(id, client_);
    }
    leave_session();
}

template <class Loaded>
void ConnectionHandler::after_load(const std::function<void(std::function<void(Loaded)>)>& start,
                                   std::function<void(const Loaded&)> then) {
    // Loading reads and converts a file, seconds for a large one: not on the strand.
    busy_ = true;
    start([this, then = std::move(then), weak = connection_,
           lifeline = context_.lifeline](Loaded loaded) mutable {
        const std::lock_guard lock(lifeline->mutex);
        auto connection = weak.lock();
        if (!lifeline->open || !connection) {
            return;
        }
        // The connection owns this handler and outlives the task.
        connection->defer([this, then = std::move(then), loaded = std::move(loaded)] {
            busy_ = false;
            then(loaded);
            handle_waiting();
        });
    });
}

void ConnectionHandler::load_then(
        std::optional<std::int64_t> id, const std::string& volume_id,
        std::function<void(std::optional<std::int64_t>, const LoadedVolume&)> then) {
    after_load<LoadedVolume>(
            [this, volume_id](std::function<void(LoadedVolume)> done) {
                context_.services.volumes.acquire_async(volume_id, std::move(done));
            },
            [id, then = std::move(then)](const LoadedVolume& volume) { then(id, volume); });
}

namespace {

// A volume that could not be loaded, as the protocol reports it (at /volume).
base::Error volume_error(const std::string& volume_id, base::Error error) {
    if (error.code != base::ErrorCode::unknown_volume) {
        // The loader's own code and location go into the message.
        error.message = "volume '" + volume_id + "' could not be loaded: " + error.to_string();
        error.code = base::ErrorCode::volume_unreadable;
    }
    error.where = "/volume";
    return error;
}

}  // namespace

void ConnectionHandler::finish_open(std::optional<std::int64_t> id, const std::string& volume_id,
                                    const LoadedVolume& volume) {
    if (!volume) {
        reply_error(id, volume_error(volume_id, volume.error()));
        return;
    }
    auto created = context_.services.sessions.create(volume_id, *volume,
                                                     initial_state(context_.config, volume),
                                                     viewer_, client_, session_.get());
    if (!created) {
        reply_error(id, created.error());
        return;
    }
    become_owner(id, std::move(created.value()), false);
}

void ConnectionHandler::finish_recreate(std::optional<std::int64_t> id,
                                        const protocol::Resume& message,
                                        const LoadedVolume& volume) {
    if (!volume) {
        reply_error(id, volume_error(*message.volume, volume.error()));
        return;
    }
    auto recreated = context_.services.sessions.recreate(
            message.session, message.owner_token, *message.volume, *volume,
            initial_state(context_.config, volume), viewer_, client_, session_.get());
    if (!recreated) {
        reply_error(id, recreated.error());
        return;
    }
    if (!recreated->created) {
        resume_held(id, message);  // another connection re-created it while the volume loaded
        return;
    }
    become_owner(id, std::move(recreated->session), true);
}

void ConnectionHandler::become_owner(std::optional<std::int64_t> id,
                                     std::shared_ptr<session::Session> session, bool recreated) {
    leave_session();
    session_ = std::move(session);
    const auto histogram = context_.services.volumes.histogram(session_->volume());
    Sinks sinks = sinks_for(session_->id());
    // Cannot fail: the session ends only when its owner, this connection, leaves.
    const auto added = session_->add_viewer(
            viewer_, std::move(sinks.frames), std::move(sinks.state_changed),
            [&](const scene::State& state, const session::DrawnLabels* /*labels: none yet*/) {
                send(protocol::opened_message(id, session_->id(),
                                              summary_of(session_->volume_summary()), *histogram,
                                              state, session_->owner_token(), recreated));
            });
    PENUMBRA_ASSERT(added.ok(), "a new session refused its owner");
    context_.sessions.set(static_cast<double>(context_.services.sessions.count()));
    base::log_info("session", std::string(recreated ? "re-created " : "opened ") + session_->id() +
                                      " on " + session_->volume_id());
}

bool ConnectionHandler::enter_session(std::optional<std::int64_t> id, const std::string& session_id,
                                      const std::optional<std::string>& owner_token) {
    // The volume's histogram, computed when it was loaded.
    const auto found = context_.services.sessions.find(session_id);
    const auto histogram = found ? context_.services.volumes.histogram(found->volume())
                                 : std::make_shared<const std::vector<std::uint64_t>>();
    Sinks sinks = sinks_for(session_id);
    // Finding the session and entering it are one step of the registry's, so a session whose
    // last viewer is leaving cannot be entered back to life; checking the owner token and
    // changing the owner are one step of the session's, so two connections resuming at once
    // cannot both win.
    auto entered = context_.services.sessions.enter(session_id, [&](session::Session& target) {
        // The labels' names and colours follow, in the same step, where a map is drawn.
        const auto welcome = [&](const scene::State& state, const session::DrawnLabels* labels) {
            const protocol::VolumeSummary volume = summary_of(target.volume_summary());
            send(owner_token
                         ? protocol::opened_message(id, target.id(), volume, *histogram, state,
                                                    target.owner_token())
                         : protocol::joined_message(id, target.id(), volume, *histogram, state));
            if (labels != nullptr) {
                send(drawn_labels_message(std::nullopt, target.id(), *labels, state));
            }
        };
        // Also when already in it: re-entering replaces the sinks, and the welcome keeps its
        // reply ahead of every state that follows it.
        return owner_token ? target.resume(viewer_, *owner_token, std::move(sinks.frames),
                                           std::move(sinks.state_changed), welcome)
                           : target.add_viewer(viewer_, std::move(sinks.frames),
                                               std::move(sinks.state_changed), welcome);
    });
    if (!entered) {
        reply_error(id, entered.error());
        return false;
    }
    if (*entered != session_) {
        leave_session();
        session_ = *entered;
    }
    return true;
}

void ConnectionHandler::resume_held(std::optional<std::int64_t> id,
                                    const protocol::Resume& message) {
    if (enter_session(id, message.session, message.owner_token)) {
        base::log_info("session", "resumed " + session_->id());
    }
}

void ConnectionHandler::handle_waiting() {
    while (!busy_ && !waiting_.empty()) {
        const protocol::Request next = std::move(waiting_.front());
        waiting_.pop_front();
        handle(next);
    }
}

bool ConnectionHandler::need_session(std::optional<std::int64_t> id) {
    if (!session_) {
        reply_error(id, base::make_error(base::ErrorCode::no_session,
                                         "open a volume or join a session first", "/type"));
        return false;
    }
    return true;
}

template <>
void ConnectionHandler::handle(std::optional<std::int64_t> id, const protocol::ListVolumes&) {
    // The last scan, or what the first has found so far: the store scans on a thread of its own.
    const session::VolumeStore& volumes = context_.services.volumes;
    const session::ScanProgress progress = volumes.progress();
    std::vector<protocol::VolumeSummary> list;
    for (const auto& entry : volumes.list()) {
        list.push_back(summary_of(entry.summary()));
    }
    const protocol::Listing listing = !progress.first_pass_done ? protocol::Listing::scanning
                                      : progress.cut_short      ? protocol::Listing::cut_short
                                                                : protocol::Listing::complete;
    send(protocol::volumes_message(id, list, listing));
}

template <>
void ConnectionHandler::handle(std::optional<std::int64_t> id, const protocol::Open& message) {
    load_then(id, message.volume,
              [this, volume_id = message.volume](std::optional<std::int64_t> request_id,
                                                 const LoadedVolume& volume) {
                  finish_open(request_id, volume_id, volume);
              });
}

template <>
void ConnectionHandler::handle(std::optional<std::int64_t> id, const protocol::Join& message) {
    enter_session(id, message.session, std::nullopt);
}

// Makes this connection the owner of a session again: the one this server holds, or one that the
// cluster's secret lets it re-create once its volume is loaded.
template <>
void ConnectionHandler::handle(std::optional<std::int64_t> id, const protocol::Resume& message) {
    if (message.volume &&
        context_.services.sessions.resume_recreates(message.session, message.owner_token)) {
        // The claim is proved before any volume is loaded for it; the session comes back under
        // its id for its viewers to find.
        load_then(id, *message.volume,
                  [this, message](std::optional<std::int64_t> request_id,
                                  const LoadedVolume& volume) {
                      finish_recreate(request_id, message, volume);
                  });
        return;
    }
    resume_held(id, message);
}

template <>
void ConnectionHandler::handle(std::optional<std::int64_t> id, const protocol::Set& message) {
    if (!need_session(id)) {
        return;
    }
    // The viewers' panels follow the owner's: each gets the new state; the owner gets it as the
    // answer.
    const auto changed = session_->change_state(viewer_, [&](scene::State& state) {
        return protocol::apply_patch(message.patch, state, context_.config.limits);
    });
    if (!changed) {
        reply_error(id, changed.error());
        return;
    }
    const std::optional<session::LabelSurfacesFor> wanted = session_->surfaces_wanted();
    if (!wanted) {
        send(protocol::set_ack_message(id, *changed));
        return;
    }
    // The state draws the label map alone with labels whose surfaces the session lacks: made on a
    // loader thread (most of a second for a large map), the connection busy meanwhile, so that the
    // frames it asks for next draw them; the answer comes once they are there.
    using Made = base::Result<std::shared_ptr<const volume::LabelSurfaces>>;
    after_load<Made>(
            [&volumes = context_.services.volumes, wanted](std::function<void(Made)> done) {
                volumes.read_async([&volumes, wanted, done = std::move(done)] {
                    try {
                        done(volumes.label_surfaces(wanted->map, wanted->visible));
                    } catch (const std::bad_alloc&) {
                        done(base::make_error(base::ErrorCode::out_of_memory,
                                              "not enough memory for the label map's surfaces",
                                              "/labels/alone"));
                    }
                });
            },
            [this, id, session = session_, wanted, state = *changed](const Made& made) {
                if (!made) {
                    reply_error(id, made.error());
                    return;
                }
                session->set_surfaces(*wanted, *made);
                send(protocol::set_ack_message(id, state));
            });
}

template <>
void ConnectionHandler::handle(std::optional<std::int64_t> id, const protocol::Render& message) {
    if (!need_session(id)) {
        return;
    }
    session_->render(context_.services.scheduler, id.value_or(-1), message.interactive, client_,
                     context_.services.sessions.quality_table());
}

template <>
void ConnectionHandler::handle(std::optional<std::int64_t> id, const protocol::Stats&) {
    protocol::StatsReport report;
    if (session_) {
        report.session = session_->id();
        report.viewers = session_->viewer_count();
        report.session_frames = session_->frame_count();
    }
    report.sessions = context_.services.sessions.count();
    report.connections = context_.connections.value();
    report.queue_depth = context_.services.scheduler.queue_depth();
    report.frame_server_p50_ms = context_.frame_server_ms.quantile(0.50);
    report.frame_server_p95_ms = context_.frame_server_ms.quantile(0.95);
    report.frame_server_p99_ms = context_.frame_server_ms.quantile(0.99);
    const session::SchedulerCounts counts = context_.services.scheduler.counts();
    report.frames_total = counts.frames;
    report.light_buffer_builds = counts.light_buffer_builds;
    report.light_buffer_reuses = counts.light_buffer_reuses;
    report.gpu_bytes_held = counts.gpu_bytes_held;
    report.renderer = context_.services.scheduler.device().renderer;
    send(protocol::stats_message(id, report));
}

template <>
void ConnectionHandler::handle(std::optional<std::int64_t> id, const protocol::Close&) {
    leave_session();
    send(protocol::ack_message(id, "close"));
}

// Loads the label map on the loader threads, then draws it in the session (Session::set_labels):
// answered by `labels`, the other viewers getting the state.
template <>
void ConnectionHandler::handle(std::optional<std::int64_t> id, const protocol::AddLabels& message) {
    if (!need_session(id)) {
        return;
    }
    if (!session_->is_owner(viewer_)) {
        reply_error(id, base::make_error(base::ErrorCode::invalid_message,
                                         "only the session's owner can change it; viewers who "
                                         "joined watch",
                                         "/type"));
        return;
    }
    const std::string volume_id = message.volume;
    after_load<session::LoadedLabels>(
            [this, volume_id](std::function<void(session::LoadedLabels)> done) {
                context_.services.volumes.acquire_labels_async(volume_id, std::move(done));
            },
            [this, id, volume_id](const session::LoadedLabels& labels) {
                if (!labels) {
                    reply_error(id, volume_error(volume_id, labels.error()));
                    return;
                }
                if (!session_) {
                    reply_error(id, base::make_error(base::ErrorCode::no_session,
                                                     "the session ended while its label map "
                                                     "loaded",
                                                     "/type"));
                    return;
                }
                draw_labels(id, volume_id, *labels);
            });
}

template <>
void ConnectionHandler::handle(std::optional<std::int64_t> id, const protocol::RemoveLabels&) {
    if (need_session(id)) {
        draw_labels(id, {}, nullptr);
    }
}

// One ray on the CPU, on the loader threads (up to a few milliseconds for a fine step through a
// large volume), the connection's other requests waiting meanwhile: one pick in flight each.
template <>
void ConnectionHandler::handle(std::optional<std::int64_t> id, const protocol::Pick& message) {
    if (!need_session(id)) {
        return;
    }
    using Picked = session::PickAnswer;
    after_load<Picked>(
            [this, session = session_, message](std::function<void(Picked)> done) {
                context_.services.volumes.read_async([session, message, done = std::move(done)] {
                    done(session->pick(message.x, message.y));
                });
            },
            [this, id, message, session_id = session_->id()](const Picked& picked) {
                answer_pick(id, session_id, message, picked);
            });
}

void ConnectionHandler::answer_pick(std::optional<std::int64_t> id, const std::string& session_id,
                                    const protocol::Pick& message,
                                    const session::PickAnswer& picked) {
    if (!picked) {
        reply_error(id, picked.error());
        return;
    }
    protocol::PickSummary summary{.x = message.x,
                                  .y = message.y,
                                  .hit = picked->hit,
                                  .value = picked->value,
                                  .hounsfield = picked->hounsfield,
                                  .label_id = picked->label_id,
                                  .label_name = picked->label_name};
    for (int axis = 0; axis < 3; ++axis) {
        summary.position[axis] = picked->patient[axis];
    }
    send(protocol::picked_message(id, session_id, summary));
}

std::optional<ConnectionHandler::ExportRequest> ConnectionHandler::export_request(
        std::optional<std::int64_t> id, double width, double height, std::string_view extension) {
    if (!need_session(id)) {
        return std::nullopt;
    }
    for (const auto& [side, where] : {std::pair{width, "/width"}, std::pair{height, "/height"}}) {
        if (side != std::floor(side)) {
            reply_error(id,
                        base::make_error(base::ErrorCode::invalid_value,
                                         "an export's sides are whole numbers of pixels", where));
            return std::nullopt;
        }
    }
    ExportRequest request{session_->make_job(-1, false), {}};
    session::RenderJob& still = request.still;
    still.client = client_;
    still.request.settings.width = static_cast<int>(width);
    still.request.settings.height = static_cast<int>(height);
    // The volume's name as far as a file name (and a Content-Disposition header) takes it.
    std::string name = session_->volume()->name;
    std::ranges::replace_if(
            name,
            [](char c) {
                return std::isalnum(static_cast<unsigned char>(c)) == 0 && c != '-' && c != '.';
            },
            '_');
    request.file_name = "penumbra-" + name + "-" + std::to_string(still.request.settings.width) +
                        "x" + std::to_string(still.request.settings.height) +
                        std::string(extension);
    return request;
}

session::Exporter::Progress ConnectionHandler::export_progress(std::optional<std::int64_t> id) {
    return [weak = connection_, id](const session::ExportStatus& status) {
        if (auto connection = weak.lock()) {
            connection->send_text(protocol::export_status_message(id, export_summary(status)));
        }
    };
}

void ConnectionHandler::track_export(std::optional<std::int64_t> id,
                                     const base::Result<std::string>& started) {
    if (!started) {
        reply_error(id, started.error());
        return;
    }
    std::erase_if(exports_, [&](const std::string& earlier) {
        return !context_.exporter.is_running(earlier);
    });
    exports_.push_back(*started);
}

// The session's view as a still of its own size, tile by tile at the lowest priority
// (session::Exporter); its statuses go to this connection while it is open.
template <>
void ConnectionHandler::handle(std::optional<std::int64_t> id, const protocol::Export& message) {
    auto request = export_request(id, message.width, message.height, ".png");
    if (!request) {
        return;
    }
    // What the PNG keeps: the session's state at the export's size.
    scene::State state = session_->state();
    state.frame.settings.width = request->still.request.settings.width;
    state.frame.settings.height = request->still.request.settings.height;
    track_export(
            id, context_.exporter.start_still(client_, std::move(request->still),
                                              context_.config.limits.max_image_side,
                                              request->file_name, session_->volume()->name,
                                              protocol::state_to_json(state), export_progress(id)));
}

// The session's view turning, as a movie: as an export of a still, frame by frame.
template <>
void ConnectionHandler::handle(std::optional<std::int64_t> id,
                               const protocol::ExportMovie& message) {
    auto request = export_request(id, message.width, message.height,
                                  message.rock > 0.0 ? "-rocking.mp4" : "-turntable.mp4");
    if (!request) {
        return;
    }
    if (message.frames != std::floor(message.frames)) {
        reply_error(id, base::make_error(base::ErrorCode::invalid_value,
                                         "a movie's frames are a whole number", "/frames"));
        return;
    }
    session::MovieSpec movie;
    movie.frames = static_cast<int>(message.frames);
    movie.rock = message.rock;
    track_export(id, context_.exporter.start_movie(client_, std::move(request->still), movie,
                                                   context_.config.limits.max_image_side,
                                                   request->file_name, export_progress(id)));
}

template <>
void ConnectionHandler::handle(std::optional<std::int64_t> id,
                               const protocol::CancelExport& message) {
    if (std::ranges::find(exports_, message.export_id) == exports_.end() ||
        !context_.exporter.cancel(message.export_id, client_)) {
        reply_error(id, base::make_error(base::ErrorCode::invalid_value,
                                         "no export of this connection with that id is running",
                                         "/export"));
    }
}

void ConnectionHandler::draw_labels(std::optional<std::int64_t> id, const std::string& volume_id,
                                    const std::shared_ptr<const volume::LabelMap>& labels) {
    auto changed = session_->set_labels(viewer_, volume_id, labels);
    if (!changed) {
        base::Error error = changed.error();
        if (error.code == base::ErrorCode::no_overlap) {
            error.code = base::ErrorCode::invalid_value;  // the wire's code for a bad value
        }
        reply_error(id, error);
        return;
    }
    send(drawn_labels_message(id, session_->id(), session_->labels(), *changed));
}

// After every handler: each alternative goes to its own specialisation of handle, and one without
// a specialisation is the deleted template, which does not compile.
void ConnectionHandler::handle(const protocol::Request& request) {
    std::visit([this, id = request.id](const auto& message) { handle(id, message); },
               request.message);
}

}  // namespace penumbra::net
