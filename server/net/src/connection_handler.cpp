#include "connection_handler.hpp"

#include <penumbra/base/assert.hpp>
#include <penumbra/base/log.hpp>
#include <penumbra/protocol/frame_header.hpp>
#include <penumbra/protocol/scene_json.hpp>
#include <penumbra/scene/camera.hpp>
#include <penumbra/volume/volume.hpp>

#include <algorithm>

namespace penumbra::net {
namespace {

using Clock = std::chrono::steady_clock;

// Beyond this many queued replies a flooding client gets no more error messages, only the
// count of what was dropped once it calms down.
constexpr std::uint64_t max_unanswered_errors = 64;

// Requests that may wait while a volume loads for this connection; more are refused.
constexpr std::size_t max_waiting_requests = 64;

protocol::SessionState to_protocol(const session::SessionState& s) {
    protocol::SessionState out;
    out.frame = s.frame;
    out.output.encoding = s.output.format == encode::ImageFormat::png ? "png" : "jpeg";
    out.output.jpeg_quality = s.output.jpeg_quality;
    out.frame_budget_ms = s.frame_budget_ms;
    return out;
}

session::SessionState from_protocol(const protocol::SessionState& s) {
    session::SessionState out;
    out.frame = s.frame;
    out.output.format =
            s.output.encoding == "png" ? encode::ImageFormat::png : encode::ImageFormat::jpeg;
    out.output.jpeg_quality = s.output.jpeg_quality;
    out.frame_budget_ms = s.frame_budget_ms;
    return out;
}

protocol::VolumeSummary summary_of(const std::string& id, const volume::Volume* v) {
    protocol::VolumeSummary out;
    out.id = id;
    out.name = v != nullptr ? v->name : id;
    out.loaded = v != nullptr;
    if (v != nullptr) {
        out.dims[0] = v->dims.x;
        out.dims[1] = v->dims.y;
        out.dims[2] = v->dims.z;
        out.spacing[0] = v->spacing.x;
        out.spacing[1] = v->spacing.y;
        out.spacing[2] = v->spacing.z;
        out.voxel_type = volume::to_string(v->type);
        out.range[0] = v->range.min;
        out.range[1] = v->range.max;
        out.hounsfield = v->hounsfield;
    }
    return out;
}

session::SessionState default_state(const ServerConfig& config) {
    session::SessionState state;
    state.frame.camera = scene::orbit_camera(25.0, 10.0, 2.6);
    state.frame.light.direction = scene::direction_from_angles(10.0, 45.0);
    auto tf = scene::preset(config.default_transfer_function);
    state.frame.transfer_function = tf ? *tf : scene::preset("grey_ramp").value();
    scene::RenderSettings& s = state.frame.settings;
    s.mode = scene::Mode::sbrc;
    s.phong = true;
    s.width = std::min(512, config.limits.max_image_side);
    s.height = s.width;
    s.light_buffer.slices = std::min(128, config.limits.max_slices);
    s.light_buffer.resolution = std::min(256, config.limits.max_light_resolution);
    return state;
}

std::vector<std::uint8_t> pack(const session::EncodedFrame& f, const std::string& session_id,
                               std::uint64_t number) {
    protocol::FrameHeader h;
    h.frame = number;
    h.request = f.request_id;
    h.session = session_id;
    h.width = f.width;
    h.height = f.height;
    h.encoding = f.format == encode::ImageFormat::png ? "png" : "jpeg";
    h.mode = scene::to_string(f.mode);
    h.interactive = f.interactive;
    h.light_buffer = f.report.light_buffer;
    for (const auto& pass : f.report.passes) {
        h.passes.push_back({pass.name, pass.gpu_ms, pass.wall_ms});
    }
    h.queued_ms = f.queued_ms;
    h.render_ms = f.render_ms;
    h.readback_ms = f.readback_ms;
    h.encode_ms = f.encode_ms;
    h.quality = f.quality;
    return protocol::pack_frame(h, f.image);
}

}  // namespace

ConnectionHandler::ConnectionHandler(Context& context, std::weak_ptr<Connection> connection,
                                     std::string client)
    : context_(context)
    , connection_(std::move(connection))
    , viewer_(context.next_viewer.fetch_add(1))
    , tokens_(context.config.limits.max_requests_per_second)
    , last_refill_(Clock::now())
    , client_(std::move(client)) {}

void ConnectionHandler::send(std::string text) {
    if (auto connection = connection_.lock()) {
        connection->send_text(std::move(text));
    }
}

void ConnectionHandler::reply_error(std::optional<std::int64_t> id, const base::Error& error) {
    if (dropped_replies_ >= max_unanswered_errors) {
        return;
    }
    // A client learns where a file is inside the data folder, never where the folder is.
    const session::VolumeStore& volumes = context_.services.volumes;
    send(protocol::error_message(id, base::Error{error.code, volumes.relative_paths(error.message),
                                                 volumes.relative_paths(error.where)}));
    context_.errors.add();
}

bool ConnectionHandler::take_token() {
    const double rate = context_.config.limits.max_requests_per_second;
    const Clock::time_point now = Clock::now();
    tokens_ = std::min(rate,
                       tokens_ + rate * std::chrono::duration<double>(now - last_refill_).count());
    last_refill_ = now;
    if (tokens_ >= 1.0) {
        tokens_ -= 1.0;
        dropped_replies_ = 0;
        return true;
    }
    ++dropped_replies_;
    return false;
}

void ConnectionHandler::on_open() {
    std::vector<std::string> modes;
    for (const auto mode :
         {scene::Mode::dvr, scene::Mode::phong, scene::Mode::half_angle, scene::Mode::sbrc,
          scene::Mode::sbrc_shell, scene::Mode::sbrc_cone, scene::Mode::reference}) {
        modes.emplace_back(scene::to_string(mode));
    }
    const render::RendererInfo& info = context_.services.scheduler.renderer_info();
    send(protocol::hello_message(context_.config.limits,
                                 {info.renderer, info.version, info.platform, info.software},
                                 modes));
}

bool ConnectionHandler::admit(std::optional<std::int64_t> id) {
    context_.messages.add();
    if (take_token()) {
        return true;
    }
    reply_error(id,
                base::make_error(protocol::code::rate_limited,
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
    reply_error(std::nullopt, base::make_error(protocol::code::invalid_message,
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
                        base::make_error(protocol::code::rate_limited,
                                         "too many requests while a volume loads", "/"));
            return;
        }
        waiting_.push_back(std::move(request.value()));
        return;
    }
    handle(*request);
}

ConnectionHandler::Sinks ConnectionHandler::sinks_for(const std::string& session_id) {
    std::weak_ptr<Connection> weak = connection_;
    Context* context = &context_;
    auto state_changed = [weak, session_id](const session::SessionState& state) {
        if (auto connection = weak.lock()) {
            connection->send_state(protocol::state_message(
                    session_id, protocol::state_to_json(to_protocol(state))));
        }
    };
    auto frames = [weak, session_id, context](
                          const base::Result<std::shared_ptr<const session::EncodedFrame>>& r,
                          std::uint64_t number) {
        auto connection = weak.lock();
        if (!connection) {
            return;
        }
        if (!r) {
            const std::string& code = r.error().code;
            if (code == "superseded" || code == "shutting_down") {
                return;  // a newer frame answers, or nobody will
            }
            connection->send_text(protocol::error_message(
                    std::nullopt,
                    base::make_error(
                            protocol::code::render_failed,
                            context->services.volumes.relative_paths(r.error().to_string()), "/")));
            context->errors.add();
            return;
        }
        const session::EncodedFrame& frame = **r;
        context->frame_server_ms.observe(frame.queued_ms + frame.render_ms + frame.readback_ms +
                                         frame.encode_ms);
        connection->send_frame(
                std::make_shared<const std::vector<std::uint8_t>>(pack(frame, session_id, number)));
    };
    return {std::move(frames), std::move(state_changed)};
}

void ConnectionHandler::leave_session() {
    if (!session_) {
        return;
    }
    if (context_.services.sessions.leave(*session_, viewer_)) {
        context_.services.scheduler.cancel(session_->id());
        context_.sessions.set(static_cast<double>(context_.services.sessions.count()));
        base::log_info("session", "closed " + session_->id());
    }
    session_.reset();
}

void ConnectionHandler::on_close() {
    leave_session();
}

void ConnectionHandler::load_then(
        std::optional<std::int64_t> id, const std::string& volume_id,
        std::function<void(std::optional<std::int64_t>, const LoadedVolume&)> then) {
    // Loading reads and converts a file, seconds for a large one: not on the strand.
    busy_ = true;
    context_.services.volumes.acquire_async(
            volume_id, [this, id, then = std::move(then), weak = connection_,
                        lifeline = context_.lifeline](LoadedVolume volume) mutable {
                const std::lock_guard lock(lifeline->mutex);
                auto connection = weak.lock();
                if (!lifeline->open || !connection) {
                    return;
                }
                // The connection owns this handler and outlives the task.
                connection->defer([this, id, then = std::move(then), volume = std::move(volume)] {
                    busy_ = false;
                    then(id, volume);
                    handle_waiting();
                });
            });
}

namespace {

// A volume that could not be loaded, as the protocol reports it (at /volume).
base::Error volume_error(const std::string& volume_id, base::Error error) {
    if (error.code != protocol::code::unknown_volume) {
        // The loader's own code and location go into the message.
        error.message = "volume '" + volume_id + "' could not be loaded: " + error.to_string();
        error.code = protocol::code::volume_unreadable;
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
    auto created = context_.services.sessions.create(
            volume_id, *volume, default_state(context_.config), viewer_, client_, session_.get());
    if (!created) {
        reply_error(id, created.error());
        return;
    }
    leave_session();
    session_ = *created;
    const auto histogram = context_.services.volumes.histogram(*volume);
    Sinks sinks = sinks_for(session_->id());
    // Cannot fail: the session ends only when its owner, this connection, leaves.
    const auto added = session_->add_viewer(
            viewer_, std::move(sinks.frames), std::move(sinks.state_changed),
            [&](const session::SessionState& state) {
                send(protocol::opened_message(
                        id, session_->id(), summary_of(volume_id, volume->get()), *histogram,
                        protocol::state_to_json(to_protocol(state)), session_->owner_token()));
            });
    PENUMBRA_ASSERT(added.ok(), "a new session refused its owner");
    context_.sessions.set(static_cast<double>(context_.services.sessions.count()));
    base::log_info("session", "opened " + session_->id() + " on " + volume_id);
}

void ConnectionHandler::resume(std::optional<std::int64_t> id, const protocol::Resume& message) {
    if (!context_.services.sessions.find(message.session) && message.volume &&
        context_.services.sessions.proves_owner(message.session, message.owner_token)) {
        // The server that held the session is gone and its owner came here: the cluster's secret
        // proves the claim (before any volume is loaded for it), and the session comes back under
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

void ConnectionHandler::finish_recreate(std::optional<std::int64_t> id,
                                        const protocol::Resume& message,
                                        const LoadedVolume& volume) {
    if (!volume) {
        reply_error(id, volume_error(*message.volume, volume.error()));
        return;
    }
    auto recreated = context_.services.sessions.recreate(
            message.session, message.owner_token, *message.volume, *volume,
            default_state(context_.config), viewer_, client_, session_.get());
    if (!recreated) {
        reply_error(id, recreated.error());
        return;
    }
    if (!recreated->created) {
        resume_held(id, message);  // another connection re-created it while the volume loaded
        return;
    }
    leave_session();
    session_ = recreated->session;
    const auto histogram = context_.services.volumes.histogram(*volume);
    Sinks sinks = sinks_for(session_->id());
    // Cannot fail: the session ends only when its owner, this connection, leaves.
    const auto added = session_->add_viewer(
            viewer_, std::move(sinks.frames), std::move(sinks.state_changed),
            [&](const session::SessionState& state) {
                send(protocol::opened_message(
                        id, session_->id(), summary_of(*message.volume, volume->get()), *histogram,
                        protocol::state_to_json(to_protocol(state)), session_->owner_token(),
                        true));
            });
    PENUMBRA_ASSERT(added.ok(), "a re-created session refused its owner");
    context_.sessions.set(static_cast<double>(context_.services.sessions.count()));
    base::log_info("session", "re-created " + session_->id() + " on " + *message.volume);
}

void ConnectionHandler::resume_held(std::optional<std::int64_t> id,
                                    const protocol::Resume& message) {
    const auto found = context_.services.sessions.find(message.session);
    const auto histogram = found ? context_.services.volumes.histogram(found->volume())
                                 : std::make_shared<const std::vector<std::uint64_t>>();
    Sinks sinks = sinks_for(message.session);
    // The check of the token and the change of owner are one step of the session's, and finding
    // it one of the registry's, so that two connections resuming at once cannot both win and an
    // ended session stays ended.
    auto resumed = context_.services.sessions.enter(message.session, [&](session::Session& target) {
        return target.resume(
                viewer_, message.owner_token, std::move(sinks.frames),
                std::move(sinks.state_changed), [&](const session::SessionState& state) {
                    send(protocol::opened_message(
                            id, target.id(), summary_of(target.volume_id(), target.volume().get()),
                            *histogram, protocol::state_to_json(to_protocol(state)),
                            target.owner_token()));
                });
    });
    if (!resumed) {
        reply_error(id, resumed.error());
        return;
    }
    if (*resumed != session_) {
        leave_session();
        session_ = *resumed;
    }
    base::log_info("session", "resumed " + session_->id());
}

void ConnectionHandler::handle_waiting() {
    while (!busy_ && !waiting_.empty()) {
        const protocol::Request next = std::move(waiting_.front());
        waiting_.pop_front();
        handle(next);
    }
}

void ConnectionHandler::handle(const protocol::Request& request) {
    const auto id = request.id;
    const auto need_session = [&]() {
        if (!session_) {
            reply_error(id, base::make_error(protocol::code::no_session,
                                             "open a volume or join a session first", "/type"));
            return false;
        }
        return true;
    };
    std::visit(
            [&](const auto& message) {
                using T = std::decay_t<decltype(message)>;
                if constexpr (std::is_same_v<T, protocol::ListVolumes>) {
                    // The last scan: the store rescans on a thread of its own.
                    std::vector<protocol::VolumeSummary> list;
                    for (const auto& entry : context_.services.volumes.list()) {
                        list.push_back(summary_of(entry.id, entry.loaded.get()));
                    }
                    send(protocol::volumes_message(id, list));
                } else if constexpr (std::is_same_v<T, protocol::Open>) {
                    load_then(id, message.volume,
                              [this, volume_id = message.volume](
                                      std::optional<std::int64_t> request_id,
                                      const LoadedVolume& volume) {
                                  finish_open(request_id, volume_id, volume);
                              });
                } else if constexpr (std::is_same_v<T, protocol::Join>) {
                    // Finding the session and joining it are one step of the registry's, so a
                    // session whose last viewer is leaving cannot be joined back to life.
                    // The volume's histogram, computed when it was loaded.
                    const auto found = context_.services.sessions.find(message.session);
                    const auto histogram =
                            found ? context_.services.volumes.histogram(found->volume())
                                  : std::make_shared<const std::vector<std::uint64_t>>();
                    Sinks sinks = sinks_for(message.session);
                    auto joined = context_.services.sessions.enter(
                            message.session, [&](session::Session& target) {
                                // Also when already in it: re-adding replaces the sinks, and the
                                // welcome keeps `joined` ahead of every state that follows it.
                                return target.add_viewer(
                                        viewer_, std::move(sinks.frames),
                                        std::move(sinks.state_changed),
                                        [&](const session::SessionState& state) {
                                            send(protocol::joined_message(
                                                    id, target.id(),
                                                    summary_of(target.volume_id(),
                                                               target.volume().get()),
                                                    *histogram,
                                                    protocol::state_to_json(to_protocol(state))));
                                        });
                            });
                    if (!joined) {
                        reply_error(id, joined.error());
                        return;
                    }
                    if (*joined != session_) {
                        leave_session();
                        session_ = *joined;
                    }
                } else if constexpr (std::is_same_v<T, protocol::Resume>) {
                    resume(id, message);
                } else if constexpr (std::is_same_v<T, protocol::Set>) {
                    if (!need_session()) {
                        return;
                    }
                    // The session keeps the one record of its owner, who may have resumed it.
                    if (!session_->is_owner(viewer_)) {
                        reply_error(id, base::make_error(protocol::code::invalid_message,
                                                         "only the session's owner can change it; "
                                                         "viewers who joined watch",
                                                         "/type"));
                        return;
                    }
                    protocol::SessionState state = to_protocol(session_->state());
                    if (auto status =
                                protocol::apply_patch(message.patch, state, context_.config.limits);
                        !status) {
                        reply_error(id, status.error());
                        return;
                    }
                    // The viewers' panels follow the owner's: each gets the new state.
                    session_->set_state(from_protocol(state), viewer_);
                    send(protocol::ack_message(id, "set"));
                } else if constexpr (std::is_same_v<T, protocol::Render>) {
                    if (!need_session()) {
                        return;
                    }
                    std::weak_ptr<session::Session> weak = session_;
                    session::RenderJob job =
                            session_->make_job(id.value_or(-1), message.interactive,
                                               context_.config.quality_table.get());
                    // The render time is this client's, whoever's session it is.
                    job.client = client_;
                    context_.services.scheduler.submit(
                            session_->id(), std::move(job),
                            [weak](base::Result<std::shared_ptr<const session::EncodedFrame>> r) {
                                if (auto s = weak.lock()) {
                                    s->deliver(r);
                                }
                            });
                } else if constexpr (std::is_same_v<T, protocol::Stats>) {
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
                    metrics::Registry& m = context_.services.metrics;
                    report.frames_total = m.counter("penumbra_frames_total", "").value();
                    report.light_buffer_builds =
                            m.counter("penumbra_light_buffer_builds_total", "").value();
                    report.light_buffer_reuses =
                            m.counter("penumbra_light_buffer_reuses_total", "").value();
                    report.gpu_bytes_held = m.gauge("penumbra_gpu_bytes_held", "").value();
                    report.renderer = context_.services.scheduler.renderer_info().renderer;
                    send(protocol::stats_message(id, report));
                } else if constexpr (std::is_same_v<T, protocol::Close>) {
                    leave_session();
                    send(protocol::ack_message(id, "close"));
                }
            },
            request.message);
}

}  // namespace penumbra::net
