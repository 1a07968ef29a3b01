#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/quality/table.hpp>
#include <penumbra/reference/pick.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/session/scheduler.hpp>
#include <penumbra/session/volume_store.hpp>
#include <penumbra/volume/label_map.hpp>
#include <penumbra/volume/volume.hpp>

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace penumbra::session {

// 128 bits in hex straight from the system's entropy source, for what must be unguessable: session
// ids (knowing the server does not let anyone join a session uninvited), owner tokens, exports.
std::string random_secret();

// A connection that receives a session's frames.
using ViewerId = std::uint64_t;

// One rendered frame of a session as its viewers receive it: one object for all of them, so that
// what is made of it for sending (its header and bytes on the wire) is made once and shared.
class SharedFrame {
public:
    using Bytes = std::shared_ptr<const std::vector<std::uint8_t>>;
    using Packer = std::function<std::vector<std::uint8_t>(const SharedFrame&)>;

    SharedFrame(std::shared_ptr<const EncodedFrame> frame, std::string session,
                std::uint64_t number);

    [[nodiscard]] const EncodedFrame& frame() const { return *frame_; }

    [[nodiscard]] const std::string& session() const { return session_; }

    // The session's number of the frame, the same for every viewer.
    [[nodiscard]] std::uint64_t number() const { return number_; }

    // The frame packed for sending: `pack` runs for the first viewer that asks, and every viewer
    // gets the same immutable bytes.
    [[nodiscard]] const Bytes& packed(const Packer& pack) const;

private:
    const std::shared_ptr<const EncodedFrame> frame_;
    const std::string session_;
    const std::uint64_t number_;
    mutable std::once_flag packed_once_;
    mutable Bytes bytes_;
};

// What a viewer receives: each frame of the session, or why one failed and which request it
// answers.
using ViewerOutcome = std::variant<std::shared_ptr<const SharedFrame>, FrameFailure>;

// Receives each ViewerOutcome. Called on a scheduler thread: it must only hand it on.
using ViewerSink = std::function<void(const ViewerOutcome& outcome)>;

// The state a new session starts from: an orbit view lit from above, `transfer_function` (a
// preset; grey_ramp if there is none of that name), and an image, light buffer and slices that
// `limits` allow.
scene::State default_state(const std::string& transfer_function, const scene::Limits& limits);

// What a pick found under its point (reference::pick), or why it could not look.
using PickAnswer = base::Result<reference::Pick>;

// The label map a session draws inside its volume, by the id the volume store lists it under;
// none (null, empty) at first.
struct DrawnLabels {
    std::string id;
    std::shared_ptr<const volume::LabelMap> map;
};

// The surfaces of a label map drawn alone (scene::Labels::alone): `map`'s with the labels
// `visible` shows (volume::label_surfaces).
struct LabelSurfacesFor {
    std::shared_ptr<const volume::LabelMap> map;
    std::vector<bool> visible;

    bool operator==(const LabelSurfacesFor&) const = default;
};

// Receives a session's state and, where the label map drawn changed with it (or, welcoming a
// viewer, where one is drawn), that map: its labels' names and colours, which the state's styles
// do not carry; else null. Called under the session's lock, so that each viewer learns of the
// states in the order they were set: it must only queue a message.
using StateSink = std::function<void(const scene::State& state, const DrawnLabels* labels)>;

// One user's view of one volume: camera, light, TF, mode and quality, and the connections that
// watch it (its owner and anyone who joined). The owner may leave (its network dropped) while
// others watch; a connection that presents the owner token takes its place. Thread-safe.
class Session : public std::enable_shared_from_this<Session> {
public:
    // `owner` opened the session and is its first viewer (with no sinks until add_viewer gives
    // them), so a session is never empty before its owner leaves; the owner token is drawn here,
    // at random.
    // `client` names who opened it (a remote address), for per-client limits.
    Session(std::string id, std::string volume_id, std::shared_ptr<const volume::Volume> volume,
            scene::State state, ViewerId owner, std::string client = {});

    // The same with the owner token given (derived from the id, see OwnerTokens).
    Session(std::string id, std::string volume_id, std::shared_ptr<const volume::Volume> volume,
            scene::State state, ViewerId owner, std::string client, std::string owner_token);

    [[nodiscard]] const std::string& id() const { return id_; }

    [[nodiscard]] const std::string& volume_id() const { return volume_id_; }

    [[nodiscard]] const std::shared_ptr<const volume::Volume>& volume() const { return volume_; }

    // What its viewers are told of its volume.
    [[nodiscard]] VolumeSummary volume_summary() const {
        return summarize(volume_id_, volume_id_, volume_.get());
    }

    // The connection that opened the session, and its client.
    [[nodiscard]] ViewerId opened_by() const { return opened_by_; }

    [[nodiscard]] const std::string& client() const { return client_; }

    // The connection that may change the session, if one is connected.
    [[nodiscard]] std::optional<ViewerId> owner() const;

    [[nodiscard]] bool is_owner(ViewerId viewer) const;

    // The secret that lets a connection become the owner again (resume). Only its owner learns it.
    [[nodiscard]] const std::string& owner_token() const { return owner_token_; }

    [[nodiscard]] scene::State state() const;

    // Replaces the state and hands it to the state sink of every viewer but `changed_by`, who
    // knows it already.
    void set_state(scene::State state, ViewerId changed_by);

    // What a viewer asks to change, applied to the current state; an error leaves it unchanged.
    using StateChange = std::function<base::Status(scene::State& state)>;

    // Lets `viewer` change the state, as set_state, if it is the owner (viewers who joined watch):
    // reading, changing and storing the state are one step, so no other change comes between.
    // Returns the state as changed. Fails with invalid_message at /type for a viewer that is not
    // the owner, or with the error of `change`.
    base::Result<scene::State> change_state(ViewerId viewer, const StateChange& change);

    [[nodiscard]] DrawnLabels labels() const;

    // Lets the owner `viewer` draw `labels` (listed as `labels_id`) inside the volume, each label
    // as its files show it (render::label_styles), or none (null): the state's labels change with
    // the map in one step, so no frame pairs a map with another's styles; every other viewer gets
    // the state with the map. Returns the state as changed; fails as change_state for a viewer that
    // is not the owner, and with no_overlap when the map lies outside the volume.
    base::Result<scene::State> set_labels(ViewerId viewer, std::string labels_id,
                                          std::shared_ptr<const volume::LabelMap> labels);

    // The surfaces the state draws and the session lacks: where it draws its label map alone and
    // has no surfaces of that map with the labels' visibility now, what to make (whoever changed
    // the state makes them off the session's lock, then set_surfaces); else none. Until they come,
    // frames draw the surfaces made last for the map, or the map inside the volume.
    [[nodiscard]] std::optional<LabelSurfacesFor> surfaces_wanted() const;

    // Keeps `surfaces`, made for `made_for`, while the session draws that map.
    void set_surfaces(LabelSurfacesFor made_for,
                      std::shared_ptr<const volume::LabelSurfaces> surfaces);

    // What lies under the point (x, y) of the view as the session's state now draws it, given as
    // fractions of the view's width and height from its top left corner (each within [0, 1]):
    // reference::pick's one ray through the pixel there, on the CPU, reading the volume in place,
    // with the label map drawn. Any viewer may ask; the state is not changed.
    [[nodiscard]] PickAnswer pick(double x, double y) const;

    // Adds a viewer, or replaces its sinks. Frames go to every viewer's `frames` sink, on a
    // scheduler thread; states that another viewer sets go to `state_changed`. `welcome` gets the
    // state the viewer starts from, under the same lock, so no change reaches the viewer before it.
    // Fails with unknown_session once the session has ended: an ended session stays ended.
    base::Status add_viewer(ViewerId viewer, ViewerSink frames, StateSink state_changed,
                            const StateSink& welcome);

    // Makes `viewer` the owner and adds it as with add_viewer, if `owner_token` is the session's
    // and no other connection owns the session now. Fails with unknown_session once the session
    // has ended (its last viewer left), invalid_value at /owner_token for another token, and
    // session_owned while another connection owns it. Its owner resuming again succeeds.
    base::Status resume(ViewerId viewer, std::string_view owner_token, ViewerSink frames,
                        StateSink state_changed, const StateSink& welcome);

    // Returns how many viewers remain; none ends the session. The owner leaving leaves the
    // session without one until someone resumes it.
    std::size_t remove_viewer(ViewerId viewer);

    [[nodiscard]] std::size_t viewer_count() const;

    // Numbers the frame and hands it to every viewer, or tells them why it failed; nobody hears
    // of a withdrawn job (a newer frame answers, or nobody is left to see it).
    void deliver(const FrameOutcome& outcome);

    // Asks `scheduler` for a frame of the current state (make_job, with the table of the registry
    // that holds the session); the outcome is delivered to the viewers of the session while it
    // lives. The render time is `client`'s, whoever's session it is.
    void render(Scheduler& scheduler, std::int64_t request_id, bool interactive,
                const std::string& client, const quality::Table* quality_table = nullptr);

    // A job for the current state, at full or interactive quality. With a frame budget and a
    // measured quality table, the most accurate setting that fits replaces the state's mode,
    // slices, light-buffer resolution and sample distance. A still that the session's earlier
    // stills say would take longer than the frame budget (scene::kStillPreviewBudgetMs without
    // one) gets a smaller preview first (scene::still_preview).
    [[nodiscard]] RenderJob make_job(std::int64_t request_id, bool interactive,
                                     const quality::Table* quality_table = nullptr) const;

    [[nodiscard]] std::uint64_t frame_count() const { return frames_.load(); }

    // The session's next frame decodes alone (a viewer's connection dropped one of its H.264
    // frames, so it waits for a keyframe). A viewer joining or resuming asks for one itself.
    void want_keyframe() { stream_->want_keyframe(); }

private:
    // change_state with mutex_ held; `labels`, where given, is the label map drawn from the
    // changed state on, which the other viewers are given with it.
    base::Result<scene::State> change_state_locked(ViewerId viewer, const StateChange& change,
                                                   std::optional<DrawnLabels> labels = {});

    const std::string id_;
    const std::string volume_id_;
    const std::shared_ptr<const volume::Volume> volume_;
    const std::string owner_token_;
    const ViewerId opened_by_;
    const std::string client_;
    mutable std::mutex mutex_;

    struct Sinks {
        ViewerSink frames;
        StateSink state_changed;
    };

    std::optional<ViewerId> owner_;
    bool ended_ = false;  // its last viewer left: nobody may come back
    scene::State state_;
    DrawnLabels labels_;
    // Its frames as one stream, in order (SessionStream).
    const std::shared_ptr<SessionStream> stream_ = std::make_shared<SessionStream>();
    LabelSurfacesFor surfaces_for_;
    std::shared_ptr<const volume::LabelSurfaces> surfaces_;  // null: none made for labels_.map
    std::map<ViewerId, Sinks> viewers_;
    std::atomic<std::uint64_t> frames_{0};

    // What the session's last still frame cost per pixel, in its mode at its sample distance:
    // the next still's time is expected from it where both are the same.
    struct StillCost {
        scene::Mode mode = scene::Mode::dvr;
        double sample_distance = 0.0;
        double ms_per_pixel = 0.0;  // wall ms of the passes that go with the pixels
    };

    static StillCost still_cost_of(const EncodedFrame& frame);
    std::optional<StillCost> still_cost_;
};

// Where owner tokens come from. Alone, a server draws each at random. The servers of a cluster
// derive it from the session id with a secret they share (HMAC-SHA256), so that any of them can
// check an owner's claim to a session that another one held, and re-create the session when that
// server is gone: its viewers then find it again under the same id.
class OwnerTokens {
public:
    // Random tokens, for a server on its own.
    OwnerTokens() = default;

    // Tokens derived from the session id with `cluster_secret` (not empty).
    explicit OwnerTokens(std::string cluster_secret);

    [[nodiscard]] bool derived() const { return !secret_.empty(); }

    [[nodiscard]] std::string token_for(const std::string& session_id) const;

    // Whether `owner_token` is the derived token of `session_id`, in constant time. Always false
    // for random tokens: only the session knows its own.
    [[nodiscard]] bool proves(const std::string& session_id, std::string_view owner_token) const;

private:
    std::string secret_;
};

// All sessions of a server, by id, up to a limit in all, per client and per connection. A session
// is in the registry exactly while it has viewers: entering one (join, resume) and leaving one
// happen under the registry's lock, so a connection joining while the last one leaves either
// joins before the session ends or finds no session, never an ended one.
class SessionRegistry {
public:
    // Owner tokens are random unless `owner_tokens` derives them (a cluster). `quality_table`:
    // the measured settings its sessions choose from for a frame-time budget (bench accuracy's
    // table); null: budgets are ignored.
    explicit SessionRegistry(int max_sessions, OwnerTokens owner_tokens = {},
                             int max_per_client = 1 << 30, int max_per_connection = 1 << 30,
                             std::shared_ptr<const quality::Table> quality_table = nullptr);

    // A session opened by connection `owner` of `client`. Fails with too_many_sessions when the
    // server, the client or the connection holds its maximum; `replacing`, the session the
    // connection leaves for the new one, is not counted.
    base::Result<std::shared_ptr<Session>> create(std::string volume_id,
                                                  std::shared_ptr<const volume::Volume> volume,
                                                  scene::State state, ViewerId owner,
                                                  const std::string& client = {},
                                                  const Session* replacing = nullptr);

    struct Recreated {
        std::shared_ptr<Session> session;
        bool created = false;  // false: the session was here already (nobody owns it through this)
    };

    // Re-creates session `id`, which this server does not hold, on `volume` with `state`, owned by
    // connection `owner` of `client`, if `owner_token` proves the claim (derived tokens only).
    // Fails with unknown_session when tokens are random (nothing can prove a claim), invalid_value
    // at /owner_token for a token that does not, and too_many_sessions at the limits of create
    // (`replacing` as there). A session of that id that exists already is returned as it is, for
    // the caller to resume.
    base::Result<Recreated> recreate(const std::string& id, std::string_view owner_token,
                                     std::string volume_id,
                                     std::shared_ptr<const volume::Volume> volume,
                                     scene::State state, ViewerId owner,
                                     const std::string& client = {},
                                     const Session* replacing = nullptr);

    [[nodiscard]] bool derives_owner_tokens() const { return owner_tokens_.derived(); }

    // Whether a resume of session `id` with `owner_token` re-creates it here (recreate): the
    // server that held it is gone and the token proves the claim. Otherwise the resume is of a
    // session this server holds (or of none).
    [[nodiscard]] bool resume_recreates(const std::string& id, std::string_view owner_token) const {
        return !find(id) && proves_owner(id, owner_token);
    }

    // Whether `owner_token` proves a claim to session `id` (derived tokens only), so that nothing
    // is loaded for a claim that recreate would refuse.
    [[nodiscard]] bool proves_owner(const std::string& id, std::string_view owner_token) const {
        return owner_tokens_.proves(id, owner_token);
    }

    [[nodiscard]] std::shared_ptr<Session> find(const std::string& id) const;

    // Finds session `id` and lets `enter` add the viewer to it (Session::add_viewer or resume),
    // both under the registry's lock. Fails with unknown_session when there is no such session,
    // or with what `enter` returns.
    base::Result<std::shared_ptr<Session>> enter(
            const std::string& id, const std::function<base::Status(Session&)>& enter);

    // Removes `viewer` from `session`; the last viewer leaving ends the session, removes it from
    // the registry in the same step and withdraws its frames from `scheduler` (nobody is left to
    // see them). Returns whether the session ended.
    bool leave(Session& session, ViewerId viewer, Scheduler& scheduler);

    [[nodiscard]] std::size_t count() const;

    // The table a session's frames are chosen from for its budget (Session::render), or null.
    [[nodiscard]] const quality::Table* quality_table() const { return quality_table_.get(); }

private:
    // Under the lock: too_many_sessions (at `where`) when the server, `client` or connection
    // `owner` holds its maximum, not counting `replacing`.
    base::Status check_limits(ViewerId owner, const std::string& client, const Session* replacing,
                              const std::string& where) const;

    int max_sessions_;
    OwnerTokens owner_tokens_;
    int max_per_client_;
    int max_per_connection_;
    const std::shared_ptr<const quality::Table> quality_table_;
    mutable std::mutex mutex_;
    std::map<std::string, std::shared_ptr<Session>> sessions_;
};

}  // namespace penumbra::session
