#include "penumbra/protocol/scene_json.hpp"

#include "json_fields.hpp"
#include "patch_document.hpp"

#include <penumbra/scene/camera.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <vector>

namespace penumbra::protocol {
namespace {

using namespace json_fields;  // NOLINT(google-build-using-namespace): local JSON vocabulary

constexpr double max_coordinate = scene::setting::coordinate.max;
// A transfer function's positions in the volume's own values: the spelling of transfer-function
// files (not of the protocol's states), turned into normalised positions as they are read.
constexpr std::string_view data_space_name = "data";

#define PENUMBRA_TRY(expression)                     \
    do {                                             \
        if (auto status_ = (expression); !status_) { \
            return status_.error();                  \
        }                                            \
    } while (false)

// Readers for a number and a vector within a setting's range.
auto in(const scene::Setting& range) {
    return [&range](const json& v, const std::string& q) {
        return number(v, q, range.min, range.max);
    };
}

auto vec3_in(const scene::Setting& range) {
    return [&range](const json& v, const std::string& q) {
        return vec3(v, q, range.min, range.max);
    };
}

// "settings/light_buffer" for "/settings/light_buffer": a JSON pointer as a setting's path.
std::string_view path_of(const std::string& pointer) {
    return std::string_view(pointer).substr(1);
}

// Whether `path` is a setting a state holds, or a part of the state that holds some
// ("settings/light_buffer").
bool is_setting_or_part(const std::string& path) {
    return std::any_of(scene::kSettings.begin(), scene::kSettings.end(),
                       [&](const scene::Setting* setting) {
                           return setting->held() &&
                                  (setting->path == path || setting->path.starts_with(path + "/"));
                       });
}

// The member of the object at `parent` (a path) that `path` lies in: "light_buffer" for
// "settings/light_buffer/slices" under "settings"; empty where `path` is not under `parent`.
std::string_view member_under(std::string_view path, std::string_view parent) {
    if (path.size() <= parent.size() + 1 || !path.starts_with(parent) ||
        path[parent.size()] != '/') {
        return {};
    }
    const std::string_view rest = path.substr(parent.size() + 1);
    return rest.substr(0, rest.find('/'));
}

// Reads the value of `setting` at `q`, checked against its kind and range.
base::Result<scene::SettingValue> read_value(const scene::Setting& setting, const json& v,
                                             const std::string& q, const Limits& limits) {
    const double max = setting.max_under(scene_limits(limits));
    switch (setting.kind) {
        case scene::SettingKind::number: {
            auto value = number(v, q, setting.min, max);
            if (!value) {
                return value.error();
            }
            return scene::SettingValue(*value, 0.0, 0.0);
        }
        case scene::SettingKind::whole: {
            auto value = integer(v, q, static_cast<int>(setting.min), static_cast<int>(max));
            if (!value) {
                return value.error();
            }
            return scene::SettingValue(*value, 0.0, 0.0);
        }
        case scene::SettingKind::boolean: {
            auto value = boolean(v, q);
            if (!value) {
                return value.error();
            }
            return scene::SettingValue(*value ? 1.0 : 0.0, 0.0, 0.0);
        }
        case scene::SettingKind::choice: {
            auto text = string(v, q, 32);
            if (!text) {
                return text.error();
            }
            const auto& names = setting.choices;
            const auto found = std::find(names.begin(), names.end(), *text);
            if (found == names.end()) {
                return field_error(base::ErrorCode::invalid_value, q,
                                   "expected " + scene::choice_list(setting, ", ", " or "));
            }
            return scene::SettingValue(static_cast<double>(found - names.begin()), 0.0, 0.0);
        }
        case scene::SettingKind::vector:
            return vec3(v, q, setting.min, max);
        case scene::SettingKind::size: {
            if (!v.is_array() || v.size() != 2) {
                return field_error(base::ErrorCode::invalid_value, q, "expected [width, height]");
            }
            const int low = static_cast<int>(setting.min);
            auto width = integer(v[0], q + "/0", low, static_cast<int>(max));
            auto height = integer(v[1], q + "/1", low, static_cast<int>(max));
            if (!width || !height) {
                return !width ? width.error() : height.error();
            }
            return scene::SettingValue(*width, *height, 0.0);
        }
    }
    return field_error(base::ErrorCode::invalid_value, q, "unknown kind of setting");
}

// The value of `setting` as the protocol spells it.
json value_json(const scene::Setting& setting, scene::SettingValue value) {
    switch (setting.kind) {
        case scene::SettingKind::number:
            return value.x;
        case scene::SettingKind::whole:
            return static_cast<int>(value.x);
        case scene::SettingKind::boolean:
            return value.x != 0.0;
        case scene::SettingKind::choice:
            return setting.choices[static_cast<std::size_t>(value.x)];
        case scene::SettingKind::vector:
            return json::array({value.x, value.y, value.z});
        case scene::SettingKind::size:
            return json::array({static_cast<int>(value.x), static_cast<int>(value.y)});
    }
    return nullptr;
}

// Applies the object `j` at `p` ("/settings") onto `state`: each setting of the table whose path
// is a member of it, then each part in it ("/settings/light_buffer"), in the table's order.
// `instructions` are the members the caller reads itself (a camera's view and orbit).
base::Status apply_object(const json& j, const std::string& p, scene::State& state,
                          const Limits& limits,
                          std::initializer_list<const char*> instructions = {}) {
    PENUMBRA_TRY(expect_object(j, p));
    const std::string path(path_of(p));
    PENUMBRA_TRY(only_fields(j, p, instructions, [&path](const std::string& key) {
        return is_setting_or_part(path + "/" + key);
    }));
    std::vector<std::string> parts;
    for (const scene::Setting* setting : scene::kSettings) {
        const std::string member(member_under(setting->path, path));
        if (!setting->held() || member.empty() || !j.contains(member)) {
            continue;
        }
        if (setting->path.size() == path.size() + 1 + member.size()) {
            auto value = read_value(*setting, j.at(member), p + "/" + member, limits);
            if (!value) {
                return value.error();
            }
            setting->write(state, *value);
        } else if (std::find(parts.begin(), parts.end(), member) == parts.end()) {
            parts.push_back(member);
        }
    }
    for (const std::string& part : parts) {
        PENUMBRA_TRY(apply_object(j.at(part), p + "/" + part, state, limits));
    }
    return base::Ok{};
}

// The camera's instructions, before its settings: a named view (the pose of that side of the
// patient, at the current distance) or an orbit around the target.
base::Status apply_camera(const json& j, const std::string& p, scene::State& state,
                          const Limits& limits) {
    scene::Camera& camera = state.frame.camera;
    PENUMBRA_TRY(expect_object(j, p));
    const auto coordinates = vec3_in(scene::setting::coordinate);
    if (j.contains("view")) {
        for (const char* other : {"orbit", "eye", "up"}) {
            if (j.contains(other)) {
                return field_error(base::ErrorCode::invalid_value, p + "/view",
                                   std::string("give either view or ") + other + ", not both");
            }
        }
        auto name = string(j.at("view"), p + "/view");
        if (!name) {
            return name.error();
        }
        const auto view = scene::parse_name<scene::View>(*name);
        if (!view) {
            return field_error(
                    base::ErrorCode::invalid_value, p + "/view",
                    "unknown view '" + *name + "' (" + scene::name_list<scene::View>(", ") + ")");
        }
        // The view keeps the camera's distance from the target it looks at (the patch's, else
        // the current one), so that naming a side never zooms.
        glm::dvec3 target = camera.target;
        PENUMBRA_TRY(optional_member(j, p, "target", target, coordinates));
        const double distance = glm::length(camera.eye - camera.target);
        camera = scene::view_camera(*view,
                                    distance > 0.0 ? distance : scene::default_camera_distance,
                                    target, camera.fov_y_degrees);
    }
    if (j.contains("orbit")) {
        if (j.contains("eye")) {
            return field_error(base::ErrorCode::invalid_value, p + "/orbit",
                               "give either orbit or eye, not both");
        }
        const json& o = j.at("orbit");
        const std::string op = p + "/orbit";
        PENUMBRA_TRY(expect_object(o, op));
        PENUMBRA_TRY(only_fields(o, op, {"azimuth", "elevation", "distance"}));
        double azimuth = 0.0;
        double elevation = 0.0;
        double distance = scene::default_camera_distance;
        PENUMBRA_TRY(optional_member(o, op, "azimuth", azimuth, in(scene::setting::orbit_azimuth)));
        PENUMBRA_TRY(optional_member(o, op, "elevation", elevation,
                                     in(scene::setting::orbit_elevation)));
        PENUMBRA_TRY(
                optional_member(o, op, "distance", distance, in(scene::setting::orbit_distance)));
        // The orbit is around the patch's target if it has one, else the current target.
        glm::dvec3 target = camera.target;
        PENUMBRA_TRY(optional_member(j, p, "target", target, coordinates));
        const double fov = camera.fov_y_degrees;
        const scene::Camera orbit = scene::orbit_camera(azimuth, elevation, distance, target);
        // The eye is sent back in `state` and must be a value `set` accepts.
        for (int axis = 0; axis < 3; ++axis) {
            if (std::abs(orbit.eye[axis]) > max_coordinate) {
                return field_error(base::ErrorCode::out_of_range, op + "/distance",
                                   "the orbit puts the eye beyond the coordinate range of ±" +
                                           json(max_coordinate).dump());
            }
        }
        camera = orbit;
        camera.fov_y_degrees = fov;
    }
    return apply_object(j, p, state, limits, {"view", "orbit"});
}

// The styles of a session's labels by id as the state writes it ("45"), looked up once per
// member of a patch.
using StylesById = std::unordered_map<std::string, scene::LabelStyle*>;

StylesById styles_by_id(scene::Labels& labels) {
    StylesById by_id;
    for (scene::LabelStyle& style : labels.styles) {
        by_id.emplace(std::to_string(style.id), &style);
    }
    return by_id;
}

// The style of label `key`, or an error at `pointer`.
base::Result<scene::LabelStyle*> style_of(const StylesById& by_id, const std::string& key,
                                          const std::string& pointer) {
    const auto found = by_id.find(key);
    if (found == by_id.end()) {
        return field_error(base::ErrorCode::invalid_value, pointer,
                           "the label map holds no label '" + key + "'");
    }
    return found->second;
}

// A style's members as a patch sets them: any of color, opacity, visible.
base::Status apply_label_style(const json& j, const std::string& p, scene::LabelStyle& style) {
    PENUMBRA_TRY(expect_object(j, p));
    PENUMBRA_TRY(only_fields(j, p, {"color", "opacity", "visible"}));
    if (j.contains("color")) {
        auto color = vec3(j["color"], p + "/color", 0.0, 1.0);
        if (!color) {
            return color.error();
        }
        style.color = *color;
    }
    if (j.contains("opacity")) {
        auto opacity = number(j["opacity"], p + "/opacity", 0.0, 1.0);
        if (!opacity) {
            return opacity.error();
        }
        style.opacity = *opacity;
    }
    if (j.contains("visible")) {
        auto visible = boolean(j["visible"], p + "/visible");
        if (!visible) {
            return visible.error();
        }
        style.visible = *visible;
    }
    return base::Ok{};
}

// The labels of the session's label map, in the order a user means them: `all` (opacity or
// visibility of every label), then `only` (these ids visible, the rest hidden), then `styles` by
// id, then `blend` and `alone`.
base::Status apply_labels(const json& j, const std::string& p, scene::Labels& labels) {
    PENUMBRA_TRY(expect_object(j, p));
    PENUMBRA_TRY(only_fields(j, p, {"all", "only", "styles", "blend", "alone"}));
    if (!labels.shown()) {
        return field_error(base::ErrorCode::invalid_value, p,
                           "the session draws no label map: add_labels first");
    }
    const StylesById by_id = styles_by_id(labels);
    if (j.contains("all")) {
        const json& all = j["all"];
        PENUMBRA_TRY(expect_object(all, p + "/all"));
        PENUMBRA_TRY(only_fields(all, p + "/all", {"opacity", "visible"}));
        for (scene::LabelStyle& style : labels.styles) {
            PENUMBRA_TRY(apply_label_style(all, p + "/all", style));
        }
    }
    if (j.contains("only")) {
        const json& only = j["only"];
        if (!only.is_array()) {
            return field_error(base::ErrorCode::invalid_value, p + "/only",
                               "expected an array of label ids");
        }
        if (only.size() > labels.styles.size()) {
            return field_error(base::ErrorCode::out_of_range, p + "/only",
                               "more ids than the label map holds labels");
        }
        for (scene::LabelStyle& style : labels.styles) {
            style.visible = false;
        }
        for (std::size_t i = 0; i < only.size(); ++i) {
            const std::string pointer = p + "/only/" + std::to_string(i);
            if (!only[i].is_number_integer()) {
                return field_error(base::ErrorCode::invalid_value, pointer, "expected a label id");
            }
            auto style = style_of(by_id, std::to_string(only[i].get<std::int64_t>()), pointer);
            if (!style) {
                return style.error();
            }
            (*style)->visible = true;
        }
    }
    if (j.contains("styles")) {
        const json& styles = j["styles"];
        PENUMBRA_TRY(expect_object(styles, p + "/styles"));
        for (const auto& [key, value] : styles.items()) {
            const std::string pointer = p + "/styles/" + pointer_token(key);
            auto style = style_of(by_id, key, pointer);
            if (!style) {
                return style.error();
            }
            PENUMBRA_TRY(apply_label_style(value, pointer, **style));
        }
    }
    if (j.contains("blend")) {
        auto blend = number(j["blend"], p + "/blend", 0.0, 1.0);
        if (!blend) {
            return blend.error();
        }
        labels.blend = *blend;
    }
    if (j.contains("alone")) {
        auto alone = boolean(j["alone"], p + "/alone");
        if (!alone) {
            return alone.error();
        }
        labels.alone = *alone;
    }
    return base::Ok{};
}

base::Result<scene::TransferFunction> transfer_function_from(
        const json& j, const std::string& p, std::optional<std::pair<double, double>> range) {
    PENUMBRA_TRY(expect_object(j, p));
    if (j.contains("preset")) {
        PENUMBRA_TRY(only_fields(j, p, {"preset"}));
        auto name = string(j.at("preset"), p + "/preset");
        if (!name) {
            return name.error();
        }
        auto tf = scene::preset(*name);
        if (!tf) {
            return field_error(base::ErrorCode::invalid_value, p + "/preset", tf.error().message);
        }
        return tf;
    }
    PENUMBRA_TRY(only_fields(j, p, {"name", "space", "colors", "opacities"}));
    scene::TransferFunction tf;
    tf.name = unnamed_transfer_function;
    PENUMBRA_TRY(optional_member(j, p, "name", tf.name, [](const json& v, const std::string& q) {
        return string(v, q, max_transfer_function_name_bytes);
    }));
    std::string space(scene::name_of(scene::PositionSpace::normalized));
    PENUMBRA_TRY(optional_member(j, p, "space", space, [](const json& v, const std::string& q) {
        return string(v, q, 16);
    }));
    const bool data_space = space == data_space_name;
    if (!data_space) {
        const auto parsed = scene::parse_name<scene::PositionSpace>(space);
        if (!parsed) {
            return field_error(base::ErrorCode::invalid_value, p + "/space",
                               "expected " + scene::name_list<scene::PositionSpace>(", ") + " or " +
                                       std::string(data_space_name));
        }
        tf.space = *parsed;
    }
    if (data_space && !range) {
        return field_error(base::ErrorCode::invalid_value, p + "/space",
                           "data positions need a volume range");
    }
    // Positions outside the range are accepted and clamped by validation's own message below.
    const auto to_unit = [&](double x) {
        if (!data_space) {
            return x;
        }
        const double width = range->second - range->first;
        return width > 0.0 ? (x - range->first) / width : 0.0;
    };
    const double position_limit = data_space ? 1e30
                                  : tf.space == scene::PositionSpace::hounsfield
                                          ? scene::max_hounsfield_position
                                          : 1.0;
    const double position_low =
            !data_space && tf.space == scene::PositionSpace::normalized ? 0.0 : -position_limit;
    for (const char* list : {"colors", "opacities"}) {
        if (!j.contains(list)) {
            continue;
        }
        const json& points = j.at(list);
        const std::string lp = p + "/" + list;
        if (!points.is_array()) {
            return field_error(base::ErrorCode::invalid_value, lp, "expected an array");
        }
        if (points.size() > max_transfer_function_points) {
            return field_error(
                    base::ErrorCode::out_of_range, lp,
                    "at most " + std::to_string(max_transfer_function_points) + " points");
        }
        const bool colors = std::string(list) == "colors";
        for (std::size_t i = 0; i < points.size(); ++i) {
            const json& point = points[i];
            const std::string pp = lp + "/" + std::to_string(i);
            PENUMBRA_TRY(expect_object(point, pp));
            PENUMBRA_TRY(only_fields(point, pp, {"x", colors ? "rgb" : "alpha"}));
            if (!point.contains("x")) {
                return field_error(base::ErrorCode::invalid_value, pp + "/x", "missing");
            }
            auto x = number(point.at("x"), pp + "/x", position_low, position_limit);
            if (!x) {
                return x.error();
            }
            if (colors) {
                if (!point.contains("rgb")) {
                    return field_error(base::ErrorCode::invalid_value, pp + "/rgb", "missing");
                }
                auto rgb = vec3(point.at("rgb"), pp + "/rgb", 0.0, 1.0);
                if (!rgb) {
                    return rgb.error();
                }
                tf.colors.push_back({to_unit(*x), *rgb});
            } else {
                if (!point.contains("alpha")) {
                    return field_error(base::ErrorCode::invalid_value, pp + "/alpha", "missing");
                }
                auto alpha = number(point.at("alpha"), pp + "/alpha", 0.0, 1.0);
                if (!alpha) {
                    return alpha.error();
                }
                tf.opacities.push_back({to_unit(*x), *alpha});
            }
        }
    }
    if (auto status = scene::validate(tf); !status) {
        // scene names the list and index ("transfer_function.opacities[2]"); as a pointer:
        // p + "/opacities/2".
        const std::string& where = status.error().where;
        const auto dot = where.find('.');
        const auto bracket = where.find('[');
        std::string pointer = p;
        if (dot != std::string::npos && bracket != std::string::npos && bracket > dot &&
            where.back() == ']') {
            pointer += "/" + where.substr(dot + 1, bracket - dot - 1) + "/" +
                       where.substr(bracket + 1, where.size() - bracket - 2);
        }
        return field_error(base::ErrorCode::invalid_value, pointer, status.error().message);
    }
    return tf;
}

}  // namespace

Patch::Patch(std::shared_ptr<const Document> document)
    : document_(std::move(document)) {
    PENUMBRA_ASSERT(document_ != nullptr && document_->object.is_object(),
                    "a Patch holds a JSON object");
}

base::Result<Patch> parse_patch(std::string_view patch_json, const Limits& limits) {
    auto parsed = parse_limited(patch_json, limits.max_json_depth);
    if (!parsed) {
        return parsed.error();
    }
    PENUMBRA_TRY(expect_object(*parsed, ""));
    return Patch(
            std::make_shared<const Patch::Document>(Patch::Document{std::move(parsed.value())}));
}

base::Status apply_patch(std::string_view patch_json, scene::State& state, const Limits& limits) {
    auto patch = parse_patch(patch_json, limits);
    if (!patch) {
        return patch.error();
    }
    return apply_patch(*patch, state, limits);
}

base::Status apply_patch(const Patch& parsed, scene::State& state, const Limits& limits) {
    const json& patch = parsed.document().object;
    PENUMBRA_TRY(only_fields(patch, "", {"transfer_function", "labels"},
                             [](const std::string& key) { return is_setting_or_part(key); }));
    scene::State next = state;
    for (const auto& [key, value] : patch.items()) {
        if (key == "camera") {
            PENUMBRA_TRY(apply_camera(value, "/camera", next, limits));
        } else if (key == "transfer_function") {
            auto tf = transfer_function_from(value, "/transfer_function", std::nullopt);
            if (!tf) {
                return tf.error();
            }
            next.frame.transfer_function = std::move(tf.value());
        } else if (key == "labels") {
            PENUMBRA_TRY(apply_labels(value, "/labels", next.frame.labels));
        } else {
            PENUMBRA_TRY(apply_object(value, "/" + key, next, limits));
        }
    }
    if (auto status = scene::validate(next, scene_limits(limits)); !status) {
        // scene names fields with dots ("camera", "light.direction", "light_buffer.slices"); as
        // a pointer into the patch: "/camera", "/light/direction", "/settings/light_buffer/slices".
        const std::string& where = status.error().where;
        const std::string part = where.substr(0, where.find('.'));
        std::string pointer =
                (is_setting_or_part(part) || part == "transfer_function" || part == "labels"
                         ? "/"
                         : "/settings/") +
                where;
        std::replace(pointer.begin(), pointer.end(), '.', '/');
        return field_error(base::ErrorCode::invalid_value, pointer, status.error().message);
    }
    state = std::move(next);
    return base::Ok{};
}

namespace json_fields {

json transfer_function_json(const scene::TransferFunction& tf) {
    json colors = json::array();
    for (const auto& c : tf.colors) {
        colors.push_back({{"x", c.x}, {"rgb", json::array({c.rgb.x, c.rgb.y, c.rgb.z})}});
    }
    json opacities = json::array();
    for (const auto& o : tf.opacities) {
        opacities.push_back({{"x", o.x}, {"alpha", o.alpha}});
    }
    return {{"name", tf.name},
            {"space", scene::to_string(tf.space)},
            {"colors", std::move(colors)},
            {"opacities", std::move(opacities)}};
}

json state_json(const scene::State& state) {
    json out = json::object();
    for (const scene::Setting* setting : scene::kSettings) {
        if (setting->held()) {
            out[json::json_pointer("/" + std::string(setting->path))] =
                    value_json(*setting, setting->read(state));
        }
    }
    out["transfer_function"] = transfer_function_json(state.frame.transfer_function);
    if (state.frame.labels.shown()) {
        out["labels"] = labels_json(state.frame.labels);
    }
    return out;
}

json labels_json(const scene::Labels& labels) {
    json styles = json::object();
    for (const scene::LabelStyle& style : labels.styles) {
        styles[std::to_string(style.id)] = {
                {"color", json::array({style.color.r, style.color.g, style.color.b})},
                {"opacity", style.opacity},
                {"visible", style.visible}};
    }
    return {{"blend", labels.blend}, {"alone", labels.alone}, {"styles", std::move(styles)}};
}

}  // namespace json_fields

std::string state_to_json(const scene::State& state) {
    return text_of(state_json(state));
}

base::Result<scene::TransferFunction> parse_transfer_function(
        std::string_view json_text, std::optional<std::pair<double, double>> data_range,
        const std::string& where) {
    auto document = parse_limited(json_text, Limits{}.max_json_depth);
    if (!document) {
        base::Error error = document.error();
        error.where = where + (error.where == "/" ? "" : error.where);
        return error;
    }
    auto tf = transfer_function_from(*document, "", data_range);
    if (!tf) {
        base::Error error = tf.error();
        error.where = where + (error.where == "/" ? "" : error.where);
        return error;
    }
    return tf;
}

}  // namespace penumbra::protocol
