#include "penumbra/protocol/messages.hpp"

#include "json_fields.hpp"
#include "patch_document.hpp"

#include <penumbra/protocol/scene_json.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <tuple>
#include <type_traits>
#include <utility>

namespace penumbra::protocol {
namespace {

using namespace json_fields;  // NOLINT(google-build-using-namespace): local JSON vocabulary

json with_id(json message, std::optional<std::int64_t> id) {
    message["v"] = protocol_version;
    if (id) {
        message["id"] = *id;
    }
    return message;
}

base::Result<std::string> required_string(const json& j, const char* key, std::size_t max) {
    const std::string pointer = std::string("/") + key;
    if (!j.contains(key)) {
        return field_error(base::ErrorCode::invalid_message, pointer,
                           std::string("missing '") + key + "'");
    }
    return string(j.at(key), pointer, max);
}

// Reads one member of a client message (messages.hpp's Member says what each kind means).
template <class Message, class Value>
base::Status read_member(const json& j, const Member<Message, Value>& member, Message& message) {
    const std::string key(member.name);
    const std::string pointer = "/" + key;
    if (std::is_same_v<Value, double> && !j.contains(key)) {
        return field_error(base::ErrorCode::invalid_message, pointer, "missing '" + key + "'");
    }
    if constexpr (std::is_same_v<Value, std::string>) {
        auto value = required_string(j, key.c_str(), member.max_bytes);
        if (!value) {
            return value.error();
        }
        message.*member.pointer = std::move(value.value());
    } else if (j.contains(key)) {
        if constexpr (std::is_same_v<Value, double>) {
            auto value = number(j.at(key), pointer, member.range.min, member.range.max);
            if (!value) {
                return value.error();
            }
            message.*member.pointer = *value;
        } else if constexpr (std::is_same_v<Value, bool>) {
            auto value = boolean(j.at(key), pointer);
            if (!value) {
                return value.error();
            }
            message.*member.pointer = *value;
        } else {
            auto value = string(j.at(key), pointer, member.max_bytes);
            if (!value) {
                return value.error();
            }
            message.*member.pointer = std::move(value.value());
        }
    }
    return base::Ok{};
}

// Whether `key` is one of the members that Message's `members()` lists (none without it).
template <class Message>
bool is_member(const std::string& key) {
    if constexpr (requires { Message::members(); }) {
        return std::apply([&](const auto&... listed) { return ((key == listed.name) || ...); },
                          Message::members());
    } else {
        return false;
    }
}

// A message made of the members it lists: the unknown ones are refused first, then each is read
// in the listed order.
template <class Message>
base::Result<Message> parse_members(const json& j, const std::string& type) {
    for (const auto& item : j.items()) {
        const std::string& key = item.key();
        if (key != "v" && key != "type" && key != "id" && !is_member<Message>(key)) {
            return field_error(base::ErrorCode::unknown_field, "/" + key,
                               "unknown field '" + key + "' in " + type);
        }
    }
    Message message;
    if constexpr (requires { Message::members(); }) {
        base::Status status = base::Ok{};
        std::apply(
                [&](const auto&... listed) {
                    ((status = status ? read_member(j, listed, message) : status), ...);
                },
                Message::members());
        if (!status) {
            return status.error();
        }
    }
    return message;
}

template <class Message>
base::Result<Message> parse_one(json& j, const std::string& type) {
    return parse_members<Message>(j, type);
}

// The message itself becomes the patch: moved, never copied or printed. It is checked once, when
// it is applied to the session's state (apply_patch), which knows every field.
template <>
base::Result<Set> parse_one<Set>(json& j, const std::string& /*type*/) {
    json patch = std::move(j);
    patch.erase("v");
    patch.erase("type");
    patch.erase("id");
    return Set{Patch(std::make_shared<const Patch::Document>(Patch::Document{std::move(patch)}))};
}

// The alternative of ClientMessage whose name is `type`, read from `j`.
template <class... Messages>
base::Result<ClientMessage> parse_message(json& j, const std::string& type,
                                          std::type_identity<std::variant<Messages...>>) {
    base::Result<ClientMessage> result = field_error(base::ErrorCode::unknown_type, "/type",
                                                     "unknown message type '" + type + "'");
    const auto parse_if_named = [&]<class Message>(std::type_identity<Message>) {
        if (type != Message::type) {
            return false;
        }
        auto parsed = parse_one<Message>(j, type);
        if (parsed) {
            result = ClientMessage(std::move(parsed.value()));
        } else {
            result = parsed.error();
        }
        return true;
    };
    (parse_if_named(std::type_identity<Messages>{}) || ...);
    return result;
}

// An integer that fits std::int64_t (nlohmann also stores integers up to 2^64 - 1, unsigned).
bool is_int64(const json& value) {
    return value.is_number_integer() &&
           (!value.is_number_unsigned() ||
            value.get<std::uint64_t>() <=
                    static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()));
}

}  // namespace

std::optional<std::int64_t> request_id_of(std::string_view text) {
    // Only the top level is kept (nested containers are dropped as they are read), so the id of
    // a message refused for its depth is found too, and nothing deep is ever built.
    using Event = json::parse_event_t;
    const json::parser_callback_t top_level_only = [](int depth, Event event, json& /*parsed*/) {
        return depth == 0 || (event != Event::object_start && event != Event::array_start);
    };
    const json j = json::parse(text, top_level_only, false);
    if (j.is_object() && j.contains("id") && is_int64(j.at("id"))) {
        return j.at("id").get<std::int64_t>();
    }
    return std::nullopt;
}

base::Result<Request> parse_request(std::string_view text, const Limits& limits) {
    if (text.size() > limits.max_message_bytes) {
        return field_error(base::ErrorCode::message_too_large, "",
                           "message of " + std::to_string(text.size()) + " bytes exceeds " +
                                   std::to_string(limits.max_message_bytes));
    }
    auto parsed = parse_limited(text, limits.max_json_depth);
    if (!parsed) {
        return parsed.error();
    }
    json& j = parsed.value();
    if (!j.is_object()) {
        return field_error(base::ErrorCode::invalid_message, "", "a message is a JSON object");
    }
    if (!j.contains("v")) {
        return field_error(base::ErrorCode::invalid_message, "/v", "missing protocol version 'v'");
    }
    if (!j.at("v").is_number_integer() || j.at("v").get<std::int64_t>() != protocol_version) {
        return field_error(
                base::ErrorCode::unsupported_version, "/v",
                "this server speaks protocol version " + std::to_string(protocol_version));
    }
    Request request;
    if (j.contains("id")) {
        if (!is_int64(j.at("id"))) {
            return field_error(base::ErrorCode::invalid_value, "/id",
                               "id must be a 64-bit signed integer");
        }
        request.id = j.at("id").get<std::int64_t>();
    }
    auto type = required_string(j, "type", 32);
    if (!type) {
        return type.error();
    }
    auto message = parse_message(j, *type, std::type_identity<ClientMessage>{});
    if (!message) {
        return message.error();
    }
    request.message = std::move(message.value());
    return request;
}

namespace {

// The longest string each member of a client message takes, keyed "type/member" (the members its
// `members()` lists, and a transfer function's name in `set`), so that a client checks its
// requests against the server's own lengths.
template <class... Messages>
json max_string_bytes(std::type_identity<std::variant<Messages...>>) {
    json lengths = json::object();
    const auto add = [&]<class Message>(std::type_identity<Message>) {
        if constexpr (requires { Message::members(); }) {
            std::apply(
                    [&](const auto&... listed) {
                        const auto add_string = [&](const auto& member) {
                            if (member.max_bytes > 0) {
                                lengths[std::string(Message::type) + "/" +
                                        std::string(member.name)] = member.max_bytes;
                            }
                        };
                        (add_string(listed), ...);
                    },
                    Message::members());
        }
    };
    (add(std::type_identity<Messages>{}), ...);
    lengths[std::string(Set::type) + "/transfer_function/name"] = max_transfer_function_name_bytes;
    return lengths;
}

// The transfer-function presets, in the shape a state reports them, so that a client offers and
// shows them without copies of its own.
json presets_json() {
    json presets = json::array();
    for (const std::string& name : scene::preset_names()) {
        presets.push_back(transfer_function_json(scene::preset(name).value()));
    }
    return presets;
}

}  // namespace

bool announces_range(const scene::Setting& setting) {
    const bool numeric =
            setting.kind == scene::SettingKind::number || setting.kind == scene::SettingKind::whole;
    return numeric && setting.limit == nullptr;
}

std::string hello_message(const Limits& limits, const RendererSummary& renderer) {
    json modes = json::array();
    for (const scene::ModeInfo& mode : scene::modes()) {
        modes.push_back({{"name", mode.name},
                         {"summary", mode.summary},
                         {"technique", scene::to_string(mode.technique)},
                         {"shadows", scene::to_string(mode.shadows)},
                         {"scattering", scene::to_string(mode.scattering)},
                         {"gradients", scene::to_string(mode.gradients)}});
    }
    // Each number's range, so that a client checks and offers what the server accepts without
    // a copy of its own, and says what the setting does; the ranges the device and the server's
    // configuration set (the image size, slices, light-buffer resolution) are its limits below.
    json ranges = json::object();
    for (const scene::Setting* setting : scene::kSettings) {
        if (!announces_range(*setting)) {
            continue;
        }
        json& announced = ranges[std::string(setting->path)];
        announced = {{"min", setting->min}, {"max", setting->max}, {"integer", setting->integer()}};
        if (!setting->summary.empty()) {
            announced["summary"] = setting->summary;
        }
    }
    json encodings = json::array();
    for (const std::string_view name : scene::setting::encoding.choices) {
        encodings.push_back(name);
    }
    return text_of(with_id(
            {{"type", "hello"},
             {"server", "penumbra"},
             {"modes", modes},
             {"ranges", ranges},
             {"presets", presets_json()},
             {"nominal_ct_range", {scene::nominal_ct_domain.min, scene::nominal_ct_domain.max}},
             {"encodings", encodings},
             {"renderer",
              {{"renderer", renderer.renderer},
               {"version", renderer.version},
               {"platform", renderer.platform},
               {"software", renderer.software}}},
             {"limits",
              {{"max_message_bytes", limits.max_message_bytes},
               {"max_image_side", limits.max_image_side},
               {"max_slices", limits.max_slices},
               {"max_light_resolution", limits.max_light_resolution},
               {"max_sessions", limits.max_sessions},
               {"max_sessions_per_client", limits.max_sessions_per_client},
               {"max_sessions_per_connection", limits.max_sessions_per_connection},
               {"max_requests_per_second", limits.max_requests_per_second},
               {"max_send_queue", limits.max_send_queue},
               {"max_frame_work", limits.max_frame_work},
               {"max_export_side", limits.max_export_side},
               {"max_movie_side", limits.max_movie_side},
               {"max_movie_frames", limits.max_movie_frames},
               {"max_json_depth", limits.max_json_depth},
               {"max_transfer_function_points", max_transfer_function_points},
               {"max_hounsfield_position", scene::max_hounsfield_position},
               {"max_string_bytes", max_string_bytes(std::type_identity<ClientMessage>{})}}}},
            std::nullopt));
}

namespace {

json volume_json(const VolumeSummary& v) {
    json out = {{"id", v.id},
                {"name", v.name},
                {"dims", {v.dims[0], v.dims[1], v.dims[2]}},
                {"spacing", {v.spacing[0], v.spacing[1], v.spacing[2]}},
                {"voxel_type", v.voxel_type},
                {"range", {v.range[0], v.range[1]}},
                {"hounsfield", v.hounsfield},
                {"loaded", v.loaded}};
    if (v.loaded) {
        out["bounds"] = {{v.bounds[0][0], v.bounds[0][1], v.bounds[0][2]},
                         {v.bounds[1][0], v.bounds[1][1], v.bounds[1][2]}};
    }
    if (v.label_map) {
        out["label_map"] = *v.label_map;
    }
    return out;
}

}  // namespace

std::string volumes_message(std::optional<std::int64_t> id,
                            const std::vector<VolumeSummary>& volumes, Listing listing) {
    json list = json::array();
    for (const auto& v : volumes) {
        list.push_back(volume_json(v));
    }
    return text_of(with_id(
            {{"type", "volumes"}, {"volumes", list}, {"listing", base::name_of(listing)}}, id));
}

std::string opened_message(std::optional<std::int64_t> id, const std::string& session,
                           const VolumeSummary& volume, const std::vector<std::uint64_t>& histogram,
                           const scene::State& state, const std::string& owner_token,
                           bool recreated) {
    json message = {
            {"type", "opened"},       {"session", session},         {"volume", volume_json(volume)},
            {"histogram", histogram}, {"state", state_json(state)}, {"owner_token", owner_token}};
    if (recreated) {
        message["recreated"] = true;
    }
    return text_of(with_id(std::move(message), id));
}

std::string joined_message(std::optional<std::int64_t> id, const std::string& session,
                           const VolumeSummary& volume, const std::vector<std::uint64_t>& histogram,
                           const scene::State& state) {
    return text_of(with_id({{"type", "joined"},
                            {"session", session},
                            {"volume", volume_json(volume)},
                            {"histogram", histogram},
                            {"state", state_json(state)}},
                           id));
}

std::string state_message(const std::string& session, const scene::State& state) {
    return text_of(with_id({{"type", "state"}, {"session", session}, {"state", state_json(state)}},
                           std::nullopt));
}

std::string labels_message(std::optional<std::int64_t> id, const std::string& session,
                           const std::string& volume, const std::vector<LabelSummary>& labels,
                           const scene::State& state) {
    json list = json::array();
    for (const LabelSummary& label : labels) {
        list.push_back({{"id", label.id},
                        {"name", label.name},
                        {"color", json::array({label.color[0], label.color[1], label.color[2]})},
                        {"voxels", label.voxels}});
    }
    return text_of(with_id({{"type", "labels"},
                            {"session", session},
                            {"volume", volume},
                            {"labels", std::move(list)},
                            {"state", state_json(state)}},
                           id));
}

std::string picked_message(std::optional<std::int64_t> id, const std::string& session,
                           const PickSummary& picked) {
    json message = {{"type", "picked"},
                    {"session", session},
                    {"x", picked.x},
                    {"y", picked.y},
                    {"hit", picked.hit}};
    if (picked.hit) {
        message["position"] =
                json::array({picked.position[0], picked.position[1], picked.position[2]});
        message["value"] = picked.value;
        message["hounsfield"] = picked.hounsfield;
        if (picked.label_id != 0) {
            message["label"] = {{"id", picked.label_id}, {"name", picked.label_name}};
        }
    }
    return text_of(with_id(std::move(message), id));
}

std::string export_status_message(std::optional<std::int64_t> id, const ExportSummary& status) {
    json message = {{"type", "export_status"}, {"export", status.export_id},
                    {"state", status.state},   {"progress", status.progress},
                    {"width", status.width},   {"height", status.height},
                    {"tiles", status.tiles}};
    if (status.frames > 0) {
        message["frames"] = status.frames;
    }
    if (!status.url.empty()) {
        message["url"] = status.url;
        message["bytes"] = status.bytes;
    }
    if (status.error) {
        message["error"] = {{"code", wire_name(status.error->code)},
                            {"message", status.error->message}};
    }
    return text_of(with_id(std::move(message), id));
}

std::string ack_message(std::optional<std::int64_t> id, std::string_view what) {
    return text_of(with_id({{"type", "ack"}, {"of", what}}, id));
}

std::string set_ack_message(std::optional<std::int64_t> id, const scene::State& state) {
    return text_of(with_id({{"type", "ack"}, {"of", Set::type}, {"state", state_json(state)}}, id));
}

std::string_view wire_name(base::ErrorCode code) {
    const bool on_the_wire =
            std::find(kWireCodes.begin(), kWireCodes.end(), code) != kWireCodes.end();
    return base::name_of(on_the_wire ? code : base::ErrorCode::internal_error);
}

std::string error_message(std::optional<std::int64_t> id, const base::Error& error) {
    return text_of(with_id({{"type", "error"},
                            {"code", wire_name(error.code)},
                            {"message", error.message},
                            {"field", error.where}},
                           id));
}

std::string stats_message(std::optional<std::int64_t> id, const std::string& stats_json) {
    return text_of(with_id({{"type", "stats"}, {"stats", json::parse(stats_json)}}, id));
}

std::string stats_message(std::optional<std::int64_t> id, const StatsReport& r) {
    json stats = {{"session", r.session ? json(*r.session) : json(nullptr)},
                  {"session_frames", r.session_frames},
                  {"viewers", r.viewers},
                  {"sessions", r.sessions},
                  {"connections", r.connections},
                  {"queue_depth", r.queue_depth},
                  {"frame_server_ms",
                   {{"p50", r.frame_server_p50_ms},
                    {"p95", r.frame_server_p95_ms},
                    {"p99", r.frame_server_p99_ms}}},
                  {"frames_total", r.frames_total},
                  {"light_buffer",
                   {{"builds", r.light_buffer_builds}, {"reuses", r.light_buffer_reuses}}},
                  {"gpu_bytes_held", r.gpu_bytes_held},
                  {"renderer", r.renderer}};
    return text_of(with_id({{"type", "stats"}, {"stats", stats}}, id));
}

}  // namespace penumbra::protocol
