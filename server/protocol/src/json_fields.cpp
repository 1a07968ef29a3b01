#include "json_fields.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <utility>
#include <vector>

namespace penumbra::protocol::json_fields {

std::string pointer_token(std::string_view name) {
    std::string token;
    for (const char c : name) {
        if (c == '~') {
            token += "~0";
        } else if (c == '/') {
            token += "~1";
        } else {
            token += c;
        }
    }
    return token;
}

base::Result<json> parse_limited(std::string_view text, int max_depth) {
    // One entry per open container: where the parser is inside it, for the error's pointer.
    struct Level {
        bool array = false;
        std::size_t index = 0;  // elements of an array read so far
        std::string key;        // the member of an object being read
    };

    std::vector<Level> levels;
    std::optional<std::string> too_deep;  // pointer of the first container beyond the limit
    const auto pointer = [&] {
        std::string out;
        for (const Level& level : levels) {
            out += '/';
            out += level.array ? std::to_string(level.index) : pointer_token(level.key);
        }
        return out;
    };
    const auto element_read = [&] {
        if (!levels.empty() && levels.back().array) {
            ++levels.back().index;
        }
    };
    using Event = json::parse_event_t;
    const json::parser_callback_t keep = [&](int /*depth*/, Event event, json& parsed) {
        if (too_deep) {
            return false;  // the document is refused: keep nothing more of it
        }
        switch (event) {
            case Event::object_start:
            case Event::array_start:
                if (std::cmp_greater_equal(levels.size(), max_depth)) {
                    too_deep = pointer();
                    return false;
                }
                levels.push_back({event == Event::array_start, 0, {}});
                return true;
            case Event::key:
                levels.back().key = parsed.get<std::string>();
                return true;
            case Event::object_end:
            case Event::array_end:
                levels.pop_back();
                element_read();
                return true;
            case Event::value:
                element_read();
                return true;
        }
        return true;
    };
    json document = json::parse(text, keep, false);
    if (document.is_discarded()) {
        return field_error(base::ErrorCode::malformed_json, "", "not valid JSON");
    }
    if (too_deep) {
        return field_error(base::ErrorCode::out_of_range, *too_deep,
                           "JSON nested deeper than " + std::to_string(max_depth) + " levels");
    }
    return document;
}

base::Status only_fields(const json& object, const std::string& pointer,
                         std::initializer_list<const char*> allowed) {
    return only_fields(object, pointer, allowed, [](const std::string&) { return false; });
}

base::Status only_fields(const json& object, const std::string& pointer,
                         std::initializer_list<const char*> allowed,
                         const std::function<bool(const std::string& key)>& also_allowed) {
    for (const auto& member : object.items()) {
        const std::string& key = member.key();
        const bool known = std::any_of(allowed.begin(), allowed.end(),
                                       [&](const char* name) { return key == name; }) ||
                           also_allowed(key);
        if (!known) {
            return field_error(base::ErrorCode::unknown_field, pointer + "/" + key,
                               "unknown field '" + key + "'");
        }
    }
    return base::Ok{};
}

base::Status expect_object(const json& value, const std::string& pointer) {
    if (!value.is_object()) {
        return field_error(base::ErrorCode::invalid_value, pointer, "expected an object");
    }
    return base::Ok{};
}

base::Result<double> number(const json& value, const std::string& pointer, double min, double max) {
    if (!value.is_number()) {
        return field_error(base::ErrorCode::invalid_value, pointer, "expected a number");
    }
    const double v = value.get<double>();
    if (!std::isfinite(v)) {
        return field_error(base::ErrorCode::invalid_value, pointer, "number must be finite");
    }
    if (v < min || v > max) {
        return field_error(base::ErrorCode::out_of_range, pointer,
                           "must be within [" + json(min).dump() + ", " + json(max).dump() + "]");
    }
    return v;
}

base::Result<int> integer(const json& value, const std::string& pointer, int min, int max) {
    if (!value.is_number_integer()) {
        return field_error(base::ErrorCode::invalid_value, pointer, "expected an integer");
    }
    const auto v = value.get<std::int64_t>();
    if (v < min || v > max) {
        return field_error(base::ErrorCode::out_of_range, pointer,
                           "must be within " + std::to_string(min) + ".." + std::to_string(max));
    }
    return static_cast<int>(v);
}

base::Result<bool> boolean(const json& value, const std::string& pointer) {
    if (!value.is_boolean()) {
        return field_error(base::ErrorCode::invalid_value, pointer, "expected true or false");
    }
    return value.get<bool>();
}

base::Result<std::string> string(const json& value, const std::string& pointer,
                                 std::size_t max_length) {
    if (!value.is_string()) {
        return field_error(base::ErrorCode::invalid_value, pointer, "expected a string");
    }
    auto text = value.get<std::string>();
    if (text.size() > max_length) {
        return field_error(base::ErrorCode::out_of_range, pointer,
                           "string longer than " + std::to_string(max_length) + " bytes");
    }
    return text;
}

base::Result<glm::dvec3> vec3(const json& value, const std::string& pointer, double min,
                              double max) {
    if (!value.is_array() || value.size() != 3) {
        return field_error(base::ErrorCode::invalid_value, pointer,
                           "expected an array of three numbers");
    }
    glm::dvec3 out(0.0);
    for (int i = 0; i < 3; ++i) {
        auto component = number(value[static_cast<std::size_t>(i)],
                                pointer + "/" + std::to_string(i), min, max);
        if (!component) {
            return component.error();
        }
        out[i] = *component;
    }
    return out;
}

}  // namespace penumbra::protocol::json_fields
