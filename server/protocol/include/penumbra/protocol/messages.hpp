#pragma once

#include <penumbra/base/enum_names.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/protocol/limits.hpp>
#include <penumbra/protocol/scene_json.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/scene/setting.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <variant>
#include <vector>

namespace penumbra::protocol {

// The codes an `error` message carries (proto/README.md lists them), in the order the protocol
// lists them: the failures a client can tell apart. Any other code reaches a client as
// internal_error (wire_name).
inline constexpr std::array kWireCodes{
        base::ErrorCode::malformed_json,      base::ErrorCode::invalid_message,
        base::ErrorCode::unknown_type,        base::ErrorCode::unknown_field,
        base::ErrorCode::unsupported_version, base::ErrorCode::invalid_value,
        base::ErrorCode::out_of_range,        base::ErrorCode::message_too_large,
        base::ErrorCode::rate_limited,        base::ErrorCode::unknown_volume,
        base::ErrorCode::volume_unreadable,   base::ErrorCode::unknown_session,
        base::ErrorCode::no_session,          base::ErrorCode::too_many_sessions,
        base::ErrorCode::session_owned,       base::ErrorCode::render_failed,
        base::ErrorCode::too_much_work,       base::ErrorCode::internal_error,
};

// The name `code` has on the wire: its own for a wire code, else internal_error's.
std::string_view wire_name(base::ErrorCode code);

// A member of a client message as the wire carries it, listed next to the message's struct by a
// static `members()`: parse_request reads each by its name, in the listed order, and refuses
// members a message does not list (unknown_field), so a message made of such members needs no
// parsing code of its own. A std::string is required (invalid_message at its pointer when
// missing); a std::optional<std::string> or a bool may be absent and then keeps the struct's
// default; a string holds at most `max_bytes` UTF-8 bytes (out_of_range beyond). A double is
// required and lies within `range` (out_of_range beyond). Wrong JSON types are invalid_value.
struct NumberRange {
    double min = 0.0;
    double max = 0.0;
};

template <class Message, class Value>
struct Member {
    std::string_view name;
    Value Message::*pointer;
    std::size_t max_bytes = 0;
    NumberRange range{};
};

template <class Message, class Value>
constexpr Member<Message, Value> member(std::string_view name, Value Message::*pointer,
                                        std::size_t max_bytes = 0) {
    static_assert(std::is_same_v<Value, std::string> ||
                          std::is_same_v<Value, std::optional<std::string>> ||
                          std::is_same_v<Value, bool>,
                  "parse_request reads a string, an optional string or a bool");
    return {name, pointer, max_bytes};
}

template <class Message>
constexpr Member<Message, double> member(std::string_view name, double Message::*pointer,
                                         NumberRange range) {
    return {name, pointer, 0, range};
}

// Client -> server. Every message carries "v": 1, a "type" and an optional client-chosen "id"
// that the answer repeats. Each message knows its type name, which is also the name of its schema
// (proto/v1/<type>.schema.json, whose `examples` are the message's examples). A message without
// `members()` has none besides "v", "type" and "id".
struct ListVolumes {
    static constexpr std::string_view type = "list_volumes";
};

struct Open {
    static constexpr std::string_view type = "open";
    std::string volume;

    static constexpr auto members() { return std::tuple{member("volume", &Open::volume, 256)}; }
};

// Any subset of the session's state (camera, light, transfer_function, settings, output); absent
// parts keep their value. Parsed, not yet checked: apply_patch (scene_json.hpp) checks each field
// once, against the state it changes, and a bad patch changes nothing. The one message that
// parse_request reads by code of its own: the message itself becomes the patch.
struct Set {
    static constexpr std::string_view type = "set";
    Patch patch;
};

struct Render {
    static constexpr std::string_view type = "render";
    bool interactive = false;  // reduced quality while the user drags; a still follows

    static constexpr auto members() {
        return std::tuple{member("interactive", &Render::interactive)};
    }
};

struct Stats {
    static constexpr std::string_view type = "stats";
};

struct Join {
    static constexpr std::string_view type = "join";
    std::string session;

    static constexpr auto members() { return std::tuple{member("session", &Join::session, 64)}; }
};

struct Close {
    static constexpr std::string_view type = "close";
};

// Becomes the owner of a session again, e.g. after the owner's connection dropped; the token is
// the one its `opened` carried.
struct Resume {
    static constexpr std::string_view type = "resume";
    std::string session;
    std::string owner_token;
    // The session's volume. A server of a cluster that shares the secret owner tokens derive from
    // re-creates a session it does not hold (its replica died) on this volume.
    std::optional<std::string> volume;

    static constexpr auto members() {
        return std::tuple{member("session", &Resume::session, 64),
                          member("owner_token", &Resume::owner_token, 64),
                          member("volume", &Resume::volume, 256)};
    }
};

// Draws a label map (a segmentation, an atlas: a volume the server lists) inside the session's
// volume, each label as its files show it; answered by `labels`. Owner only.
struct AddLabels {
    static constexpr std::string_view type = "add_labels";
    std::string volume;

    static constexpr auto members() {
        return std::tuple{member("volume", &AddLabels::volume, 256)};
    }
};

// Draws no label map; answered by `labels` with none.
struct RemoveLabels {
    static constexpr std::string_view type = "remove_labels";
};

// What lies under a point of the session's view (the frame as the client shows it): where the eye
// sees a surface there, in patient millimetres, the scan's value and the label drawn there;
// answered by `picked`. Any viewer of the session may ask.
struct Pick {
    static constexpr std::string_view type = "pick";
    static constexpr NumberRange fraction{0.0, 1.0};
    double x = 0.0;  // of the view's width, from its left edge
    double y = 0.0;  // of the view's height, from its top edge

    static constexpr auto members() {
        return std::tuple{member("x", &Pick::x, fraction), member("y", &Pick::y, fraction)};
    }
};

// Renders the session's view, as its state now draws it, as a still of width x height pixels (up
// to hello.limits.max_export_side a side, larger than a frame may be: in tiles), each tile refined
// as the session's stills are, into a PNG that keeps the state that drew it; at the lowest
// priority, so that no session's frames wait for it. Answered by `export_status` as it runs, and
// when done with the URL the PNG is downloaded from (over HTTP, from this server, while it is
// kept). Any viewer of the session may ask; a connection's exports end with it.
struct Export {
    static constexpr std::string_view type = "export";
    static constexpr NumberRange side{1.0, 16384.0};
    double width = 0.0;
    double height = 0.0;

    static constexpr auto members() {
        return std::tuple{member("width", &Export::width, side),
                          member("height", &Export::height, side)};
    }
};

// Renders the session's view turning as a movie (a turntable): `frames` frames of width x height
// (even, up to hello.limits.max_movie_side), the view turned about its up axis through the camera's
// target a whole turn, or rocking between -rock and +rock degrees where rock > 0, each frame
// refined as the first needed, into an MP4 (H.264) at 30 frames a second. Otherwise as `export`:
// the lowest priority, export_status, the download, the limits per client and server.
struct ExportMovie {
    static constexpr std::string_view type = "export_movie";
    static constexpr NumberRange side{2.0, 16384.0};
    static constexpr NumberRange frame_count{1.0, 100000.0};
    static constexpr NumberRange rock_degrees{0.0, 180.0};
    double width = 0.0;
    double height = 0.0;
    double frames = 0.0;
    double rock = 0.0;

    static constexpr auto members() {
        return std::tuple{member("width", &ExportMovie::width, side),
                          member("height", &ExportMovie::height, side),
                          member("frames", &ExportMovie::frames, frame_count),
                          member("rock", &ExportMovie::rock, rock_degrees)};
    }
};

// Stops an export the connection started; its export_status then says `cancelled`.
struct CancelExport {
    static constexpr std::string_view type = "cancel_export";
    std::string export_id;

    static constexpr auto members() {
        return std::tuple{member("export", &CancelExport::export_id, 64)};
    }
};

// A new client message is its struct above (its `type` and, for members, `members()`) and its
// alternative here; its handler, a specialisation of ConnectionHandler::handle in net (without one
// net does not compile); and its schema, proto/v1/<type>.schema.json, with a description and
// examples. scripts/update-schema.sh then writes its name into common.schema.json's client_type
// and its row into proto/README.md; protocol_test fails until the schema and those agree.
using ClientMessage =
        std::variant<ListVolumes, Open, Set, Render, Stats, Join, Close, Resume, AddLabels,
                     RemoveLabels, Pick, Export, ExportMovie, CancelExport>;

template <typename Variant>
struct MessageTypes;

template <typename... Messages>
struct MessageTypes<std::variant<Messages...>> {
    static constexpr std::array<std::string_view, sizeof...(Messages)> names{Messages::type...};
};

// The client message types, in the order of ClientMessage's alternatives: what the tests of the
// schemas and examples walk, so that a new message needs no list of its own there.
inline constexpr auto kClientMessageTypes = MessageTypes<ClientMessage>::names;

struct Request {
    std::optional<std::int64_t> id;
    ClientMessage message;
};

// Parses and validates one text message. Errors carry a code from `code::` and, in `where`, the
// JSON pointer of the offending field ("/camera/eye/1").
base::Result<Request> parse_request(std::string_view text, const Limits& limits);

// The id of a message that failed to parse, if one could be read, so the error can echo it.
std::optional<std::int64_t> request_id_of(std::string_view text);

// Server -> client text messages, serialised to JSON.
struct VolumeSummary {
    std::string id;
    std::string name;
    std::uint32_t dims[3] = {0, 0, 0};
    double spacing[3] = {1, 1, 1};
    std::string voxel_type;
    double range[2] = {0, 0};
    bool hounsfield = false;  // the values are Hounsfield units: the CT presets suit it
    bool loaded = false;
    // Once loaded: the box in patient space (RAS mm) that holds the voxels, min then max corner.
    double bounds[2][3] = {{0, 0, 0}, {0, 0, 0}};
    // In `volumes` only: the file says it is a label map, what add_labels draws.
    std::optional<bool> label_map;
};

// Where the server's listing of its data folder stands, as `volumes` says it.
enum class Listing {
    scanning,   // the first scan is under way: more volumes may follow
    complete,   // the last scan listed every volume
    cut_short,  // the last scan stopped at its budget: some volumes may be missing
};

inline constexpr std::array<base::EnumName<Listing>, 3> kListingNames{{
        {Listing::scanning, "scanning"},
        {Listing::complete, "complete"},
        {Listing::cut_short, "cut_short"},
}};
static_assert(base::names_each_value(kListingNames));

constexpr std::span<const base::EnumName<Listing>> names_of(Listing) {
    return kListingNames;
}

struct RendererSummary {
    std::string renderer;
    std::string version;
    std::string platform;
    bool software = false;  // a software rasteriser (llvmpipe): no GPU
};

// Whether hello.ranges announces `setting`'s range: a number or a whole number that no device or
// server configuration bounds (those bounds are hello.limits).
bool announces_range(const scene::Setting& setting);

// Lists every mode of scene's mode table with what it computes, so clients need not know them.
std::string hello_message(const Limits& limits, const RendererSummary& renderer);
std::string volumes_message(std::optional<std::int64_t> id,
                            const std::vector<VolumeSummary>& volumes, Listing listing);
// `state` is the session's full state (what `set` can change), as the client should show it.
// `opened` answers open and resume and carries the owner token, which a viewer never learns.
// `recreated`: a resume re-created the session here with the default state (the replica that held
// it is gone), so the owner sends its state back.
std::string opened_message(std::optional<std::int64_t> id, const std::string& session,
                           const VolumeSummary& volume, const std::vector<std::uint64_t>& histogram,
                           const scene::State& state, const std::string& owner_token,
                           bool recreated = false);
std::string joined_message(std::optional<std::int64_t> id, const std::string& session,
                           const VolumeSummary& volume, const std::vector<std::uint64_t>& histogram,
                           const scene::State& state);
// The session's full state after its owner changed it, for the other connections in the session.
// It answers no request of theirs, so it has no id.
std::string state_message(const std::string& session, const scene::State& state);

// One label of a label map as `labels` lists it.
struct LabelSummary {
    std::int64_t id = 0;
    std::string name;
    std::uint8_t color[3] = {0, 0, 0};
    std::uint64_t voxels = 0;
};

// The label map the session draws (`volume`, its id in volumes; empty for none) and its labels,
// with the state its labels' styles are now in: answers add_labels and remove_labels.
std::string labels_message(std::optional<std::int64_t> id, const std::string& session,
                           const std::string& volume, const std::vector<LabelSummary>& labels,
                           const scene::State& state);

// What a pick found under its point (x, y, as asked): `hit` false where the view shows nothing
// there; else the point in patient space (RAS mm), the scan's value (`hounsfield`: in HU) and the
// label drawn there (`label_id` 0: none).
struct PickSummary {
    double x = 0.0;
    double y = 0.0;
    bool hit = false;
    double position[3] = {0, 0, 0};
    double value = 0.0;
    bool hounsfield = false;
    std::int64_t label_id = 0;
    std::string label_name;
};

std::string picked_message(std::optional<std::int64_t> id, const std::string& session,
                           const PickSummary& picked);

// Where an export stands (session::ExportStatus as the wire carries it): `url` once done, `error`
// once failed.
struct ExportSummary {
    std::string export_id;
    std::string state;  // running, done, failed, cancelled
    double progress = 0.0;
    int width = 0;
    int height = 0;
    int tiles = 0;
    int frames = 0;  // a movie's; 0 for a still
    std::size_t bytes = 0;
    std::string url;
    std::optional<base::Error> error;
};

std::string export_status_message(std::optional<std::int64_t> id, const ExportSummary& status);

std::string ack_message(std::optional<std::int64_t> id, std::string_view what);
// Answers a `set` with the state as it now is, the patch applied: the client shows what the
// server made of it (an orbit's eye, a view's pose, a preset's points) without rules of its own.
std::string set_ack_message(std::optional<std::int64_t> id, const scene::State& state);
std::string error_message(std::optional<std::int64_t> id, const base::Error& error);
std::string stats_message(std::optional<std::int64_t> id, const std::string& stats_json);

// What `stats` reports: the asking connection's session and the server as a whole.
struct StatsReport {
    std::optional<std::string> session;
    std::uint64_t session_frames = 0;
    std::size_t viewers = 0;
    std::size_t sessions = 0;
    double connections = 0;
    std::size_t queue_depth = 0;
    double frame_server_p50_ms = 0;  // queued + render + readback + encode, from the histogram
    double frame_server_p95_ms = 0;
    double frame_server_p99_ms = 0;
    std::uint64_t frames_total = 0;
    std::uint64_t light_buffer_builds = 0;
    std::uint64_t light_buffer_reuses = 0;
    double gpu_bytes_held = 0;
    std::string renderer;
};

std::string stats_message(std::optional<std::int64_t> id, const StatsReport& report);

}  // namespace penumbra::protocol
