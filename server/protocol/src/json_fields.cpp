#include "json_fields.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace penumbra::protocol::json_fields {

base::Status only_fields(const json& object, const std::string& pointer,
                         std::initializer_list<const char*> allowed) {
    for (const auto& [key, value] : object.items()) {
        const bool known = std::any_of(allowed.begin(), allowed.end(),
                                       [&](const char* name) { return key == name; });
        if (!known) {
            return field_error("unknown_field", pointer + "/" + key,
                               "unknown field '" + key + "'");
        }
    }
    return base::Ok{};
}

base::Status expect_object(const json& value, const std::string& pointer) {
    if (!value.is_object()) {
        return field_error("invalid_value", pointer, "expected an object");
    }
    return base::Ok{};
}

base::Result<double> number(const json& value, const std::string& pointer, double min,
                            double max) {
    if (!value.is_number()) {
        return field_error("invalid_value", pointer, "expected a number");
    }
    const double v = value.get<double>();
    if (!std::isfinite(v)) {
        return field_error("invalid_value", pointer, "number must be finite");
    }
    if (v < min || v > max) {
        return field_error("out_of_range", pointer,
                           "must be within [" + json(min).dump() + ", " + json(max).dump() + "]");
    }
    return v;
}

base::Result<int> integer(const json& value, const std::string& pointer, int min, int max) {
    if (!value.is_number_integer()) {
        return field_error("invalid_value", pointer, "expected an integer");
    }
    const auto v = value.get<std::int64_t>();
    if (v < min || v > max) {
        return field_error("out_of_range", pointer,
                           "must be within " + std::to_string(min) + ".." + std::to_string(max));
    }
    return static_cast<int>(v);
}

base::Result<bool> boolean(const json& value, const std::string& pointer) {
    if (!value.is_boolean()) {
        return field_error("invalid_value", pointer, "expected true or false");
    }
    return value.get<bool>();
}

base::Result<std::string> string(const json& value, const std::string& pointer,
                                 std::size_t max_length) {
    if (!value.is_string()) {
        return field_error("invalid_value", pointer, "expected a string");
    }
    auto text = value.get<std::string>();
    if (text.size() > max_length) {
        return field_error("out_of_range", pointer,
                           "string longer than " + std::to_string(max_length) + " bytes");
    }
    return text;
}

base::Result<glm::dvec3> vec3(const json& value, const std::string& pointer, double min,
                              double max) {
    if (!value.is_array() || value.size() != 3) {
        return field_error("invalid_value", pointer, "expected an array of three numbers");
    }
    glm::dvec3 out(0.0);
    for (int i = 0; i < 3; ++i) {
        auto component = number(value[static_cast<std::size_t>(i)], pointer + "/" + std::to_string(i),
                                min, max);
        if (!component) {
            return component.error();
        }
        out[i] = *component;
    }
    return out;
}

}  // namespace penumbra::protocol::json_fields
