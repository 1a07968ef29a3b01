#include "penumbra/protocol/messages.hpp"

#include "json_fields.hpp"
#include "patch_document.hpp"

#include <penumbra/protocol/scene_json.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
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
        return field_error(code::invalid_message, pointer, std::string("missing '") + key + "'");
    }
    return string(j.at(key), pointer, max);
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
        return field_error(code::message_too_large, "",
                           "message of " + std::to_string(text.size()) + " bytes exceeds " +
                                   std::to_string(limits.max_message_bytes));
    }
    auto parsed = parse_limited(text, limits.max_json_depth);
    if (!parsed) {
        return parsed.error();
    }
    json& j = parsed.value();
    if (!j.is_object()) {
        return field_error(code::invalid_message, "", "a message is a JSON object");
    }
    if (!j.contains("v")) {
        return field_error(code::invalid_message, "/v", "missing protocol version 'v'");
    }
    if (!j.at("v").is_number_integer() || j.at("v").get<std::int64_t>() != protocol_version) {
        return field_error(
                code::unsupported_version, "/v",
                "this server speaks protocol version " + std::to_string(protocol_version));
    }
    Request request;
    if (j.contains("id")) {
        if (!is_int64(j.at("id"))) {
            return field_error(code::invalid_value, "/id", "id must be a 64-bit signed integer");
        }
        request.id = j.at("id").get<std::int64_t>();
    }
    auto type = required_string(j, "type", 32);
    if (!type) {
        return type.error();
    }
    const auto fields = [&](std::initializer_list<const char*> extra) {
        std::vector<const char*> allowed = {"v", "type", "id"};
        allowed.insert(allowed.end(), extra.begin(), extra.end());
        for (const auto& member : j.items()) {
            const std::string& key = member.key();
            if (std::find_if(allowed.begin(), allowed.end(),
                             [&](const char* a) { return key == a; }) == allowed.end()) {
                return base::Status(field_error(code::unknown_field, "/" + key,
                                                "unknown field '" + key + "' in " + *type));
            }
        }
        return base::Status(base::Ok{});
    };
    if (*type == ListVolumes::type || *type == Stats::type || *type == Close::type) {
        if (auto status = fields({}); !status) {
            return status.error();
        }
        if (*type == ListVolumes::type) {
            request.message = ListVolumes{};
        } else if (*type == Stats::type) {
            request.message = Stats{};
        } else {
            request.message = Close{};
        }
        return request;
    }
    if (*type == Open::type) {
        if (auto status = fields({"volume"}); !status) {
            return status.error();
        }
        auto volume = required_string(j, "volume", 256);
        if (!volume) {
            return volume.error();
        }
        request.message = Open{*volume};
        return request;
    }
    if (*type == Join::type) {
        if (auto status = fields({"session"}); !status) {
            return status.error();
        }
        auto session = required_string(j, "session", 64);
        if (!session) {
            return session.error();
        }
        request.message = Join{*session};
        return request;
    }
    if (*type == Resume::type) {
        if (auto status = fields({"session", "owner_token", "volume"}); !status) {
            return status.error();
        }
        auto session = required_string(j, "session", 64);
        if (!session) {
            return session.error();
        }
        auto owner_token = required_string(j, "owner_token", 64);
        if (!owner_token) {
            return owner_token.error();
        }
        Resume resume{*session, *owner_token, std::nullopt};
        if (j.contains("volume")) {
            auto volume = required_string(j, "volume", 256);
            if (!volume) {
                return volume.error();
            }
            resume.volume = *volume;
        }
        request.message = std::move(resume);
        return request;
    }
    if (*type == Render::type) {
        if (auto status = fields({"interactive"}); !status) {
            return status.error();
        }
        Render render;
        if (j.contains("interactive")) {
            auto interactive = boolean(j.at("interactive"), "/interactive");
            if (!interactive) {
                return interactive.error();
            }
            render.interactive = *interactive;
        }
        request.message = render;
        return request;
    }
    if (*type == Set::type) {
        // The message itself becomes the patch: moved, never copied or printed. It is checked once,
        // when it is applied to the session's state (apply_patch), which knows every field.
        json patch = std::move(j);
        patch.erase("v");
        patch.erase("type");
        patch.erase("id");
        request.message = Set{
                Patch(std::make_shared<const Patch::Document>(Patch::Document{std::move(patch)}))};
        return request;
    }
    return field_error(code::unknown_type, "/type", "unknown message type '" + *type + "'");
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
    // Each setting's range, so that a client checks and offers what the server accepts without
    // a copy of its own.
    json ranges = json::object();
    for (const scene::SettingRange* range : scene::kSettingRanges) {
        ranges[std::string(range->field)] = {
                {"min", range->min}, {"max", range->max}, {"integer", range->integer}};
    }
    return with_id({{"type", "hello"},
                    {"server", "penumbra"},
                    {"modes", modes},
                    {"ranges", ranges},
                    {"encodings", {"jpeg", "png"}},
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
                      {"max_json_depth", limits.max_json_depth}}}},
                   std::nullopt)
            .dump();
}

namespace {

json volume_json(const VolumeSummary& v) {
    return {{"id", v.id},
            {"name", v.name},
            {"dims", {v.dims[0], v.dims[1], v.dims[2]}},
            {"spacing", {v.spacing[0], v.spacing[1], v.spacing[2]}},
            {"voxel_type", v.voxel_type},
            {"range", {v.range[0], v.range[1]}},
            {"hounsfield", v.hounsfield},
            {"loaded", v.loaded}};
}

}  // namespace

std::string volumes_message(std::optional<std::int64_t> id,
                            const std::vector<VolumeSummary>& volumes) {
    json list = json::array();
    for (const auto& v : volumes) {
        list.push_back(volume_json(v));
    }
    return with_id({{"type", "volumes"}, {"volumes", list}}, id).dump();
}

std::string opened_message(std::optional<std::int64_t> id, const std::string& session,
                           const VolumeSummary& volume, const std::vector<std::uint64_t>& histogram,
                           const std::string& state_json, const std::string& owner_token,
                           bool recreated) {
    json message = {{"type", "opened"},
                    {"session", session},
                    {"volume", volume_json(volume)},
                    {"histogram", histogram},
                    {"state", json::parse(state_json)},
                    {"owner_token", owner_token}};
    if (recreated) {
        message["recreated"] = true;
    }
    return with_id(std::move(message), id).dump();
}

std::string joined_message(std::optional<std::int64_t> id, const std::string& session,
                           const VolumeSummary& volume, const std::vector<std::uint64_t>& histogram,
                           const std::string& state_json) {
    return with_id({{"type", "joined"},
                    {"session", session},
                    {"volume", volume_json(volume)},
                    {"histogram", histogram},
                    {"state", json::parse(state_json)}},
                   id)
            .dump();
}

std::string state_message(const std::string& session, const std::string& state_json) {
    return with_id({{"type", "state"}, {"session", session}, {"state", json::parse(state_json)}},
                   std::nullopt)
            .dump();
}

std::string ack_message(std::optional<std::int64_t> id, std::string_view what) {
    return with_id({{"type", "ack"}, {"of", what}}, id).dump();
}

std::string error_message(std::optional<std::int64_t> id, const base::Error& error) {
    return with_id({{"type", "error"},
                    {"code", error.code},
                    {"message", error.message},
                    {"field", error.where}},
                   id)
            .dump();
}

std::string stats_message(std::optional<std::int64_t> id, const std::string& stats_json) {
    return with_id({{"type", "stats"}, {"stats", json::parse(stats_json)}}, id).dump();
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
    return with_id({{"type", "stats"}, {"stats", stats}}, id).dump();
}

}  // namespace penumbra::protocol
