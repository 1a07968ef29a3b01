#include "penumbra/session/session.hpp"

#include <penumbra/base/secret.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/camera.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <variant>

#include <openssl/evp.h>
#include <openssl/hmac.h>

namespace penumbra::session {
// Not a generator seeded once: a single id seen by a viewer would betray its seed, and with it
// every other id and token.
std::string random_secret() {
    static std::mutex mutex;
    static std::random_device device;
    const std::lock_guard lock(mutex);
    std::string text;
    for (int word = 0; word < 4; ++word) {
        char hex[9];
        std::snprintf(hex, sizeof hex, "%08x", static_cast<unsigned>(device()));
        text += hex;
    }
    return text;
}

SharedFrame::SharedFrame(std::shared_ptr<const EncodedFrame> frame, std::string session,
                         std::uint64_t number)
    : frame_(std::move(frame))
    , session_(std::move(session))
    , number_(number) {}

const SharedFrame::Bytes& SharedFrame::packed(const Packer& pack) const {
    std::call_once(packed_once_, [&] {
        bytes_ = std::make_shared<const std::vector<std::uint8_t>>(pack(*this));
    });
    return bytes_;
}

scene::State default_state(const std::string& transfer_function, const scene::Limits& limits) {
    scene::State state;
    state.frame = scene::starting_frame(limits);
    auto tf = scene::preset(transfer_function);
    state.frame.transfer_function = tf ? *tf : scene::preset("grey_ramp").value();
    return state;
}

// Hex digits of an owner token: 128 bits, as many as a random one.
constexpr std::size_t owner_token_digits = 32;

OwnerTokens::OwnerTokens(std::string cluster_secret)
    : secret_(std::move(cluster_secret)) {}

std::string OwnerTokens::token_for(const std::string& session_id) const {
    if (secret_.empty()) {
        return random_secret();
    }
    // The purpose goes into the message, so that the secret's HMAC of a session id means nothing
    // anywhere else.
    const std::string message = "penumbra owner token\n" + session_id;
    std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
    unsigned int length = 0;
    HMAC(EVP_sha256(), secret_.data(), static_cast<int>(secret_.size()),
         reinterpret_cast<const unsigned char*>(message.data()), message.size(), digest.data(),
         &length);
    std::string text;
    for (unsigned int i = 0; i < length && text.size() < owner_token_digits; ++i) {
        char hex[3];
        std::snprintf(hex, sizeof hex, "%02x", digest[i]);
        text += hex;
    }
    return text;
}

bool OwnerTokens::proves(const std::string& session_id, std::string_view owner_token) const {
    return derived() && base::same_secret(owner_token, token_for(session_id));
}

Session::Session(std::string id, std::string volume_id,
                 std::shared_ptr<const volume::Volume> volume, scene::State state, ViewerId owner,
                 std::string client)
    : Session(std::move(id), std::move(volume_id), std::move(volume), std::move(state), owner,
              std::move(client), random_secret()) {}

Session::Session(std::string id, std::string volume_id,
                 std::shared_ptr<const volume::Volume> volume, scene::State state, ViewerId owner,
                 std::string client, std::string owner_token)
    : id_(std::move(id))
    , volume_id_(std::move(volume_id))
    , volume_(std::move(volume))
    , owner_token_(std::move(owner_token))
    , opened_by_(owner)
    , client_(std::move(client))
    , owner_(owner)
    , state_(std::move(state)) {
    viewers_[owner] = {};
}

std::optional<ViewerId> Session::owner() const {
    const std::lock_guard lock(mutex_);
    return owner_;
}

bool Session::is_owner(ViewerId viewer) const {
    const std::lock_guard lock(mutex_);
    return owner_ == viewer;
}

scene::State Session::state() const {
    const std::lock_guard lock(mutex_);
    return state_;
}

void Session::set_state(scene::State state, ViewerId changed_by) {
    const std::lock_guard lock(mutex_);
    state_ = std::move(state);
    for (const auto& [viewer, sinks] : viewers_) {
        if (viewer != changed_by && sinks.state_changed) {
            sinks.state_changed(state_, nullptr);
        }
    }
}

base::Result<scene::State> Session::change_state(ViewerId viewer, const StateChange& change) {
    const std::lock_guard lock(mutex_);
    return change_state_locked(viewer, change);
}

base::Result<scene::State> Session::change_state_locked(ViewerId viewer, const StateChange& change,
                                                        std::optional<DrawnLabels> labels) {
    if (owner_ != viewer) {
        return base::make_error(base::ErrorCode::invalid_message,
                                "only the session's owner can change it; viewers who joined watch",
                                "/type");
    }
    scene::State next = state_;
    if (auto status = change(next); !status) {
        return status.error();
    }
    state_ = std::move(next);
    if (labels) {
        labels_ = std::move(*labels);
        if (surfaces_for_.map != labels_.map) {
            surfaces_for_ = {};
            surfaces_.reset();
        }
    }
    for (const auto& [other, sinks] : viewers_) {
        if (other != viewer && sinks.state_changed) {
            sinks.state_changed(state_, labels ? &labels_ : nullptr);
        }
    }
    return state_;
}

DrawnLabels Session::labels() const {
    const std::lock_guard lock(mutex_);
    return labels_;
}

std::optional<LabelSurfacesFor> Session::surfaces_wanted() const {
    const std::lock_guard lock(mutex_);
    const scene::Labels& labels = state_.frame.labels;
    if (!labels.alone || !labels.shown() || !labels_.map) {
        return std::nullopt;
    }
    LabelSurfacesFor wanted{labels_.map, scene::visibility(labels)};
    if (surfaces_ && surfaces_for_ == wanted) {
        return std::nullopt;
    }
    return wanted;
}

void Session::set_surfaces(LabelSurfacesFor made_for,
                           std::shared_ptr<const volume::LabelSurfaces> surfaces) {
    const std::lock_guard lock(mutex_);
    if (made_for.map == labels_.map) {
        surfaces_for_ = std::move(made_for);
        surfaces_ = std::move(surfaces);
    }
}

PickAnswer Session::pick(double x, double y) const {
    if (!volume_) {
        return base::make_error(base::ErrorCode::no_volume, "the session holds no volume", "/type");
    }
    scene::FrameRequest frame;
    DrawnLabels labels;
    std::shared_ptr<const volume::LabelSurfaces> surfaces;
    {
        const std::lock_guard lock(mutex_);
        frame = state_.frame;
        labels = labels_;
        if (frame.labels.alone) {
            surfaces = surfaces_;
        }
    }
    // The pixel whose square holds the point; the right and bottom edges belong to the last.
    const auto pixel = [](double fraction, int size) {
        return std::clamp(static_cast<int>(std::floor(fraction * size)), 0, size - 1);
    };
    const int px = pixel(x, frame.settings.width);
    const int py = pixel(y, frame.settings.height);
    if (!surfaces) {
        return reference::pick(*volume_, frame, labels.map.get(), px, py);
    }
    // The view draws the map alone: the surface is the surfaces', the value the scan's there.
    auto picked = reference::pick(surfaces->indicator, scene::labels_alone_request(frame),
                                  &surfaces->labels, px, py);
    if (picked && picked->hit) {
        picked->value = reference::value_at(*volume_, picked->patient);
        picked->hounsfield = volume_->hounsfield;
    }
    return picked;
}

base::Result<scene::State> Session::set_labels(ViewerId viewer, std::string labels_id,
                                               std::shared_ptr<const volume::LabelMap> labels) {
    if (labels) {
        if (auto status = volume::check_overlap(*volume_, labels->indices); !status) {
            base::Error error = status.error();
            error.where = "/volume";
            return error;
        }
    }
    const auto styles = labels ? render::label_styles(*labels) : scene::Labels{};
    DrawnLabels drawn{labels ? std::move(labels_id) : std::string{}, std::move(labels)};
    const std::lock_guard lock(mutex_);
    return change_state_locked(
            viewer,
            [&](scene::State& state) {
                state.frame.labels = styles;
                return base::Status{base::Ok{}};
            },
            std::move(drawn));
}

base::Status Session::add_viewer(ViewerId viewer, ViewerSink frames, StateSink state_changed,
                                 const StateSink& welcome) {
    const std::lock_guard lock(mutex_);
    if (ended_) {
        return base::make_error(base::ErrorCode::unknown_session, "no session '" + id_ + "'",
                                "/session");
    }
    viewers_[viewer] = {std::move(frames), std::move(state_changed)};
    stream_->want_keyframe();  // it has seen no frame of the stream yet
    if (welcome) {
        welcome(state_, labels_.map ? &labels_ : nullptr);
    }
    return base::Ok{};
}

base::Status Session::resume(ViewerId viewer, std::string_view owner_token, ViewerSink frames,
                             StateSink state_changed, const StateSink& welcome) {
    const std::lock_guard lock(mutex_);
    if (ended_) {
        // Its last connection left while the resuming one was finding it.
        return base::make_error(base::ErrorCode::unknown_session, "no session '" + id_ + "'",
                                "/session");
    }
    // The token before the owner, so that only the owner learns whether it is still connected.
    if (!base::same_secret(owner_token, owner_token_)) {
        return base::make_error(base::ErrorCode::invalid_value,
                                "not the owner token of this session", "/owner_token");
    }
    if (owner_ && *owner_ != viewer) {
        return base::make_error(base::ErrorCode::session_owned,
                                "the session's owner is still connected; resume it after that "
                                "connection has closed",
                                "/session");
    }
    owner_ = viewer;
    viewers_[viewer] = {std::move(frames), std::move(state_changed)};
    stream_->want_keyframe();
    if (welcome) {
        welcome(state_, labels_.map ? &labels_ : nullptr);
    }
    return base::Ok{};
}

std::size_t Session::remove_viewer(ViewerId viewer) {
    const std::lock_guard lock(mutex_);
    viewers_.erase(viewer);
    if (owner_ == viewer) {
        owner_.reset();
    }
    if (viewers_.empty()) {
        ended_ = true;
    }
    return viewers_.size();
}

std::size_t Session::viewer_count() const {
    const std::lock_guard lock(mutex_);
    return viewers_.size();
}

Session::StillCost Session::still_cost_of(const EncodedFrame& frame) {
    // Only the passes that go with the pixels: not an upload, a table or a light buffer built
    // once for many frames.
    double ms = 0.0;
    for (const auto& pass : frame.report.passes) {
        if (pass.name == "raycast" || pass.name == "half_angle" || pass.name == "accumulate" ||
            pass.name == "readback") {
            ms += render::measured_ms(pass);
        }
    }
    const double pixels = std::max(1.0, static_cast<double>(frame.width) * frame.height);
    return {frame.mode, frame.sample_distance, ms / pixels};
}

void Session::deliver(const FrameOutcome& outcome) {
    if (std::holds_alternative<Withdrawn>(outcome)) {
        return;
    }
    const auto* frame = std::get_if<std::shared_ptr<const EncodedFrame>>(&outcome);
    std::vector<ViewerSink> sinks;
    {
        const std::lock_guard lock(mutex_);
        // The still itself: its refinement steps march at another sample distance.
        if (frame != nullptr && !(*frame)->interactive && !(*frame)->preview &&
            (*frame)->refinement_step == 0) {
            still_cost_ = still_cost_of(**frame);
        }
        sinks.reserve(viewers_.size());
        for (const auto& [viewer, viewer_sinks] : viewers_) {
            sinks.push_back(viewer_sinks.frames);
        }
    }
    const ViewerOutcome result =
            std::holds_alternative<FrameFailure>(outcome)
                    ? ViewerOutcome(std::get<FrameFailure>(outcome))
                    : std::make_shared<const SharedFrame>(
                              std::get<std::shared_ptr<const EncodedFrame>>(outcome), id_,
                              ++frames_);
    for (const auto& sink : sinks) {
        if (sink) {
            sink(result);
        }
    }
}

void Session::render(Scheduler& scheduler, std::int64_t request_id, bool interactive,
                     const std::string& client, const quality::Table* quality_table) {
    RenderJob job = make_job(request_id, interactive, quality_table);
    job.client = client;
    scheduler.submit(id_, std::move(job), [weak = weak_from_this()](const FrameOutcome& outcome) {
        if (auto session = weak.lock()) {
            session->deliver(outcome);
        }
    });
}

RenderJob Session::make_job(std::int64_t request_id, bool interactive,
                            const quality::Table* quality_table) const {
    scene::State current;
    RenderJob job;
    job.volume = volume_;
    std::optional<StillCost> still_cost;
    {
        // The state and the label map its labels style, read together.
        const std::lock_guard lock(mutex_);
        current = state_;
        still_cost = still_cost_;
        if (current.frame.labels.shown()) {
            job.labels = labels_.map;
            if (current.frame.labels.alone && surfaces_) {
                // The map alone: its surfaces are the volume drawn, their labels the map.
                job.volume =
                        std::shared_ptr<const volume::Volume>(surfaces_, &surfaces_->indicator);
                job.labels = std::shared_ptr<const volume::LabelMap>(surfaces_, &surfaces_->labels);
                current.frame = scene::labels_alone_request(std::move(current.frame));
            }
        }
    }
    std::string budget_note;
    if (current.frame_budget_ms > 0.0 && quality_table != nullptr) {
        const auto choice =
                quality::choose(*quality_table, current.frame_budget_ms,
                                current.frame.settings.width, current.frame.settings.height);
        if (choice) {
            current.frame = quality::apply(std::move(current.frame), choice->setting.key);
            budget_note = "; " + choice->describe(current.frame_budget_ms);
        }
    }
    job.output = current.output;
    job.stream = stream_;
    job.request_id = request_id;
    job.interactive = interactive;
    if (interactive) {
        auto [reduced, description] = scene::interactive_request(current.frame);
        job.request = std::move(reduced);
        job.quality = std::move(description) + budget_note;
    } else {
        job.request = current.frame;
        job.quality = "still: full quality" + budget_note;
        const scene::RenderSettings& s = job.request.settings;
        if (s.jitter && scene::is_ray_cast(s.mode)) {
            job.refinement_steps = current.refinement_steps;
            job.refinement_threshold = current.refinement_threshold;
        }
        if (still_cost && still_cost->mode == s.mode &&
            still_cost->sample_distance == s.sample_distance) {
            const double budget = current.frame_budget_ms > 0.0 ? current.frame_budget_ms
                                                                : scene::kStillPreviewBudgetMs;
            const double expected = still_cost->ms_per_pixel * s.width * s.height;
            if (auto preview = scene::still_preview(job.request, expected, budget)) {
                const scene::RenderSettings& p = preview->settings;
                char said[160];
                std::snprintf(said, sizeof said,
                              "still preview: %dx%d, the still at %dx%d expected in %.0f ms",
                              p.width, p.height, s.width, s.height, expected);
                job.preview = RenderJob::Preview{std::move(*preview), said + budget_note};
            }
        }
    }
    job.submitted = Clock::now();
    return job;
}

SessionRegistry::SessionRegistry(int max_sessions, OwnerTokens owner_tokens, int max_per_client,
                                 int max_per_connection,
                                 std::shared_ptr<const quality::Table> quality_table)
    : max_sessions_(max_sessions)
    , owner_tokens_(std::move(owner_tokens))
    , max_per_client_(max_per_client)
    , max_per_connection_(max_per_connection)
    , quality_table_(std::move(quality_table)) {}

base::Status SessionRegistry::check_limits(ViewerId owner, const std::string& client,
                                           const Session* replacing,
                                           const std::string& where) const {
    int of_client = 0;
    int of_connection = 0;
    for (const auto& [id, session] : sessions_) {
        if (session.get() != replacing) {
            of_client += session->client() == client ? 1 : 0;
            of_connection += session->opened_by() == owner ? 1 : 0;
        }
    }
    const auto refuse = [&](const std::string& who, int maximum) {
        return base::make_error(
                base::ErrorCode::too_many_sessions,
                who + " already holds its maximum of " + std::to_string(maximum) + " sessions",
                where);
    };
    if (static_cast<int>(sessions_.size()) >= max_sessions_) {
        return refuse("the server", max_sessions_);
    }
    if (of_client >= max_per_client_) {
        return refuse("this client (" + client + ")", max_per_client_);
    }
    if (of_connection >= max_per_connection_) {
        return refuse("this connection", max_per_connection_);
    }
    return base::Ok{};
}

base::Result<std::shared_ptr<Session>> SessionRegistry::create(
        std::string volume_id, std::shared_ptr<const volume::Volume> volume, scene::State state,
        ViewerId owner, const std::string& client, const Session* replacing) {
    const std::lock_guard lock(mutex_);
    if (auto allowed = check_limits(owner, client, replacing, "/volume"); !allowed) {
        return allowed.error();
    }
    std::string id = random_secret();
    std::string owner_token = owner_tokens_.token_for(id);
    auto session =
            std::make_shared<Session>(std::move(id), std::move(volume_id), std::move(volume),
                                      std::move(state), owner, client, std::move(owner_token));
    sessions_.emplace(session->id(), session);
    return session;
}

base::Result<SessionRegistry::Recreated> SessionRegistry::recreate(
        const std::string& id, std::string_view owner_token, std::string volume_id,
        std::shared_ptr<const volume::Volume> volume, scene::State state, ViewerId owner,
        const std::string& client, const Session* replacing) {
    if (!owner_tokens_.derived()) {
        return base::make_error(base::ErrorCode::unknown_session, "no session '" + id + "'",
                                "/session");
    }
    if (!owner_tokens_.proves(id, owner_token)) {
        return base::make_error(base::ErrorCode::invalid_value,
                                "not the owner token of this session", "/owner_token");
    }
    const std::lock_guard lock(mutex_);
    if (const auto found = sessions_.find(id); found != sessions_.end()) {
        return Recreated{found->second, false};
    }
    if (auto allowed = check_limits(owner, client, replacing, "/session"); !allowed) {
        return allowed.error();
    }
    auto session =
            std::make_shared<Session>(id, std::move(volume_id), std::move(volume), std::move(state),
                                      owner, client, std::string(owner_token));
    sessions_.emplace(id, session);
    return Recreated{session, true};
}

std::shared_ptr<Session> SessionRegistry::find(const std::string& id) const {
    const std::lock_guard lock(mutex_);
    const auto found = sessions_.find(id);
    return found == sessions_.end() ? nullptr : found->second;
}

base::Result<std::shared_ptr<Session>> SessionRegistry::enter(
        const std::string& id, const std::function<base::Status(Session&)>& enter) {
    const std::lock_guard lock(mutex_);
    const auto found = sessions_.find(id);
    if (found == sessions_.end()) {
        return base::make_error(base::ErrorCode::unknown_session, "no session '" + id + "'",
                                "/session");
    }
    if (auto status = enter(*found->second); !status) {
        return status.error();
    }
    return found->second;
}

bool SessionRegistry::leave(Session& session, ViewerId viewer, Scheduler& scheduler) {
    {
        const std::lock_guard lock(mutex_);
        if (session.remove_viewer(viewer) > 0) {
            return false;
        }
        const auto found = sessions_.find(session.id());
        if (found != sessions_.end() && found->second.get() == &session) {
            sessions_.erase(found);
        }
    }
    // Outside the registry's lock: the scheduler takes its own.
    scheduler.cancel(session.id());
    return true;
}

std::size_t SessionRegistry::count() const {
    const std::lock_guard lock(mutex_);
    return sessions_.size();
}

}  // namespace penumbra::session
