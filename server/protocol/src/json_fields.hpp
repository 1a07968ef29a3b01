#pragma once

// Strict reading of JSON fields: every failure names the JSON pointer of the field.

#include <penumbra/base/result.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include <functional>
#include <initializer_list>
#include <string>
#include <string_view>

namespace penumbra::protocol::json_fields {

using nlohmann::json;

// The text of a message the server sends. Its strings may quote a stranger's bytes (a file's name,
// a token an error quotes) that are no UTF-8, which nlohmann's dump() would throw on: those become
// U+FFFD instead, so no file and no message can make the server fail while it answers.
inline std::string text_of(const json& message) {
    return message.dump(-1, ' ', false, json::error_handler_t::replace);
}

inline base::Error field_error(base::ErrorCode code, const std::string& pointer,
                               const std::string& message) {
    return base::make_error(code, message, pointer.empty() ? "/" : pointer);
}

// Parses untrusted JSON text whose containers nest at most `max_depth` deep (the outermost
// counts 1). The depth is checked while parsing: nlohmann's parser keeps its own stack on the
// heap, but copying, printing, comparing and destroying a document recurse once per level, so a
// deeper document must never become a `json` value. Not JSON: "malformed_json" at "/"; too deep:
// "out_of_range" at the pointer of the first container beyond the limit.
base::Result<json> parse_limited(std::string_view text, int max_depth);

// Rejects members other than `allowed`.
base::Status only_fields(const json& object, const std::string& pointer,
                         std::initializer_list<const char*> allowed);

// Rejects members other than `allowed` and those `also_allowed` accepts.
base::Status only_fields(const json& object, const std::string& pointer,
                         std::initializer_list<const char*> allowed,
                         const std::function<bool(const std::string& key)>& also_allowed);

base::Status expect_object(const json& value, const std::string& pointer);

base::Result<double> number(const json& value, const std::string& pointer, double min, double max);

base::Result<int> integer(const json& value, const std::string& pointer, int min, int max);

base::Result<bool> boolean(const json& value, const std::string& pointer);

base::Result<std::string> string(const json& value, const std::string& pointer,
                                 std::size_t max_length = 256);

base::Result<glm::dvec3> vec3(const json& value, const std::string& pointer, double min,
                              double max);

// Reads `object[key]` with `read` into `target` when the member exists.
template <class T, class Read>
base::Status optional_member(const json& object, const std::string& pointer, const char* key,
                             T& target, Read&& read) {
    if (!object.contains(key)) {
        return base::Ok{};
    }
    auto value = read(object.at(key), pointer + "/" + key);
    if (!value) {
        return value.error();
    }
    target = *value;
    return base::Ok{};
}

// A member name as a JSON pointer token: "~" and "/" escaped (RFC 6901).
std::string pointer_token(std::string_view name);

// A transfer function in the shape `set` takes and a state reports: {"name", "space", "colors":
// [{"x", "rgb"}], "opacities": [{"x", "alpha"}]} (hello's presets too).
json transfer_function_json(const scene::TransferFunction& tf);

// A session's state as `state` messages carry it and `set` takes it: every setting of scene's
// table at its path, and the transfer function.
json state_json(const scene::State& state);

// A session's label styles as the state carries them: {"blend", "styles": {"<id>": {"color",
// "opacity", "visible"}}}, keyed by id so that a patch of the same shape changes them.
json labels_json(const scene::Labels& labels);

}  // namespace penumbra::protocol::json_fields
