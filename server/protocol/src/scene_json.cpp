#include "penumbra/protocol/scene_json.hpp"

#include "json_fields.hpp"
#include "patch_document.hpp"

#include <penumbra/encode/encode.hpp>
#include <penumbra/scene/camera.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

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

// Readers for a number, a whole number and a vector within a setting's range.
auto in(const scene::SettingRange& range) {
    return [&range](const json& v, const std::string& q) {
        return number(v, q, range.min, range.max);
    };
}

auto whole_in(const scene::SettingRange& range) {
    return [&range](const json& v, const std::string& q) {
        return integer(v, q, static_cast<int>(range.min), static_cast<int>(range.max));
    };
}

auto vec3_in(const scene::SettingRange& range) {
    return [&range](const json& v, const std::string& q) {
        return vec3(v, q, range.min, range.max);
    };
}

// A setting's JSON pointer, "/" + its field: "/settings/light_buffer/compensation".
std::string pointer_of(const scene::SettingRange& range) {
    return "/" + std::string(range.field);
}

// Whether `range` is a setting that a request holds (it has a `write`) and a member of the object
// at `object_pointer`.
bool is_member_of(const scene::SettingRange& range, const std::string& object_pointer) {
    const std::string pointer = pointer_of(range);
    return range.write != nullptr && pointer.size() > object_pointer.size() + 1 &&
           pointer.starts_with(object_pointer + "/") &&
           pointer.find('/', object_pointer.size() + 1) == std::string::npos;
}

// Whether `key` of the object at `object_pointer` is one of the table's settings.
bool is_table_setting(const std::string& object_pointer, const std::string& key) {
    return std::any_of(scene::kSettingRanges.begin(), scene::kSettingRanges.end(),
                       [&](const scene::SettingRange* range) {
                           return is_member_of(*range, object_pointer) &&
                                  pointer_of(*range) == object_pointer + "/" + key;
                       });
}

// Rejects members of the object at `p` other than `allowed` and the table's settings in it.
base::Status only_fields_and_settings(const json& j, const std::string& p,
                                      std::initializer_list<const char*> allowed) {
    return only_fields(j, p, allowed,
                       [&p](const std::string& key) { return is_table_setting(p, key); });
}

// Reads each of the table's settings that is a member of the object `j` at `p` into the request,
// in the table's order, within its range.
base::Status apply_table_settings(const json& j, const std::string& p,
                                  scene::FrameRequest& request) {
    for (const scene::SettingRange* range : scene::kSettingRanges) {
        if (!is_member_of(*range, p)) {
            continue;
        }
        const std::string key = pointer_of(*range).substr(p.size() + 1);
        if (!j.contains(key)) {
            continue;
        }
        double value = 0.0;
        if (range->integer) {
            PENUMBRA_TRY(optional_member(j, p, key.c_str(), value, whole_in(*range)));
        } else {
            PENUMBRA_TRY(optional_member(j, p, key.c_str(), value, in(*range)));
        }
        range->write(request, value);
    }
    return base::Ok{};
}

template <class Enum, class Parse>
base::Status apply_enum(const json& j, const std::string& p, const char* key, Enum& target,
                        Parse&& parse, const std::string& expected) {
    if (!j.contains(key)) {
        return base::Ok{};
    }
    auto text = string(j.at(key), p + "/" + key, 32);
    if (!text) {
        return text.error();
    }
    auto parsed = parse(*text);
    if (!parsed) {
        return field_error("invalid_value", p + "/" + key, "expected " + expected);
    }
    target = *parsed;
    return base::Ok{};
}

// A value named in its enum's table (scene/enum_names.hpp); the error lists the names.
template <scene::NamedEnum Enum>
base::Status apply_enum(const json& j, const std::string& p, const char* key, Enum& target) {
    return apply_enum(j, p, key, target, scene::parse_name<Enum>, scene::choices<Enum>());
}

base::Status apply_camera(const json& j, const std::string& p, scene::FrameRequest& request) {
    scene::Camera& camera = request.camera;
    PENUMBRA_TRY(expect_object(j, p));
    PENUMBRA_TRY(only_fields_and_settings(j, p, {"eye", "target", "up", "orbit", "view"}));
    const auto coordinates = vec3_in(scene::setting::coordinate);
    if (j.contains("view")) {
        for (const char* other : {"orbit", "eye", "up"}) {
            if (j.contains(other)) {
                return field_error("invalid_value", p + "/view",
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
                    "invalid_value", p + "/view",
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
            return field_error("invalid_value", p + "/orbit", "give either orbit or eye, not both");
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
                return field_error("out_of_range", op + "/distance",
                                   "the orbit puts the eye beyond the coordinate range of ±" +
                                           json(max_coordinate).dump());
            }
        }
        camera = orbit;
        camera.fov_y_degrees = fov;
    }
    PENUMBRA_TRY(optional_member(j, p, "eye", camera.eye, coordinates));
    PENUMBRA_TRY(optional_member(j, p, "target", camera.target, coordinates));
    PENUMBRA_TRY(optional_member(j, p, "up", camera.up, coordinates));
    return apply_table_settings(j, p, request);
}

base::Status apply_light(const json& j, const std::string& p, scene::FrameRequest& request) {
    scene::Light& light = request.light;
    PENUMBRA_TRY(expect_object(j, p));
    PENUMBRA_TRY(only_fields_and_settings(j, p, {"type", "direction", "position", "color"}));
    PENUMBRA_TRY(apply_enum(j, p, "type", light.type));
    const auto coordinates = vec3_in(scene::setting::coordinate);
    PENUMBRA_TRY(optional_member(j, p, "direction", light.direction, coordinates));
    PENUMBRA_TRY(optional_member(j, p, "position", light.position, coordinates));
    PENUMBRA_TRY(optional_member(j, p, "color", light.color, vec3_in(scene::setting::colour)));
    return apply_table_settings(j, p, request);
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
            return field_error("invalid_value", p + "/preset", tf.error().message);
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
            return field_error("invalid_value", p + "/space",
                               "expected " + scene::name_list<scene::PositionSpace>(", ") + " or " +
                                       std::string(data_space_name));
        }
        tf.space = *parsed;
    }
    if (data_space && !range) {
        return field_error("invalid_value", p + "/space", "data positions need a volume range");
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
            return field_error("invalid_value", lp, "expected an array");
        }
        if (points.size() > max_transfer_function_points) {
            return field_error(
                    "out_of_range", lp,
                    "at most " + std::to_string(max_transfer_function_points) + " points");
        }
        const bool colors = std::string(list) == "colors";
        for (std::size_t i = 0; i < points.size(); ++i) {
            const json& point = points[i];
            const std::string pp = lp + "/" + std::to_string(i);
            PENUMBRA_TRY(expect_object(point, pp));
            PENUMBRA_TRY(only_fields(point, pp, {"x", colors ? "rgb" : "alpha"}));
            if (!point.contains("x")) {
                return field_error("invalid_value", pp + "/x", "missing");
            }
            auto x = number(point.at("x"), pp + "/x", position_low, position_limit);
            if (!x) {
                return x.error();
            }
            if (colors) {
                if (!point.contains("rgb")) {
                    return field_error("invalid_value", pp + "/rgb", "missing");
                }
                auto rgb = vec3(point.at("rgb"), pp + "/rgb", 0.0, 1.0);
                if (!rgb) {
                    return rgb.error();
                }
                tf.colors.push_back({to_unit(*x), *rgb});
            } else {
                if (!point.contains("alpha")) {
                    return field_error("invalid_value", pp + "/alpha", "missing");
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
        return field_error("invalid_value", pointer, status.error().message);
    }
    return tf;
}

auto int_range_of(int lo, int hi) {
    return [lo, hi](const json& v, const std::string& q) { return integer(v, q, lo, hi); };
}

base::Status apply_settings(const json& j, const std::string& p, scene::FrameRequest& request,
                            double& frame_budget_ms, int& refinement_steps, const Limits& limits) {
    scene::RenderSettings& s = request.settings;
    PENUMBRA_TRY(expect_object(j, p));
    PENUMBRA_TRY(
            only_fields_and_settings(j, p,
                                     {"mode", "compositing", "stage", "size", "background", "phong",
                                      "empty_space_skipping", "jitter", "shading", "light_buffer",
                                      "scattering", "frame_budget_ms", "refinement_steps"}));
    PENUMBRA_TRY(
            apply_enum(j, p, "mode", s.mode, scene::parse_mode, "one of " + scene::mode_names()));
    PENUMBRA_TRY(apply_enum(j, p, "compositing", s.compositing));
    PENUMBRA_TRY(apply_enum(j, p, "stage", s.stage));
    if (j.contains("size")) {
        const json& size = j.at("size");
        if (!size.is_array() || size.size() != 2) {
            return field_error("invalid_value", p + "/size", "expected [width, height]");
        }
        auto w = integer(size[0], p + "/size/0", 1, limits.max_image_side);
        auto h = integer(size[1], p + "/size/1", 1, limits.max_image_side);
        if (!w || !h) {
            return !w ? w.error() : h.error();
        }
        s.width = *w;
        s.height = *h;
    }
    PENUMBRA_TRY(apply_table_settings(j, p, request));
    PENUMBRA_TRY(
            optional_member(j, p, "background", s.background, vec3_in(scene::setting::colour)));
    PENUMBRA_TRY(optional_member(j, p, "phong", s.phong, boolean));
    PENUMBRA_TRY(optional_member(j, p, "empty_space_skipping", s.empty_space_skipping, boolean));
    PENUMBRA_TRY(optional_member(j, p, "jitter", s.jitter, boolean));
    PENUMBRA_TRY(optional_member(j, p, "frame_budget_ms", frame_budget_ms,
                                 in(scene::setting::frame_budget_ms)));
    PENUMBRA_TRY(optional_member(j, p, "refinement_steps", refinement_steps,
                                 whole_in(scene::setting::refinement_steps)));
    if (j.contains("shading")) {
        const json& sh = j.at("shading");
        const std::string sp = p + "/shading";
        PENUMBRA_TRY(expect_object(sh, sp));
        PENUMBRA_TRY(only_fields_and_settings(sh, sp, {}));
        PENUMBRA_TRY(apply_table_settings(sh, sp, request));
    }
    if (j.contains("light_buffer")) {
        const json& lb = j.at("light_buffer");
        const std::string lp = p + "/light_buffer";
        PENUMBRA_TRY(expect_object(lb, lp));
        PENUMBRA_TRY(
                only_fields_and_settings(lb, lp, {"slices", "resolution", "builder", "lookup"}));
        PENUMBRA_TRY(optional_member(lb, lp, "slices", s.light_buffer.slices,
                                     int_range_of(1, limits.max_slices)));
        PENUMBRA_TRY(optional_member(lb, lp, "resolution", s.light_buffer.resolution,
                                     int_range_of(1, limits.max_light_resolution)));
        PENUMBRA_TRY(apply_enum(lb, lp, "builder", s.light_buffer.builder));
        PENUMBRA_TRY(apply_table_settings(lb, lp, request));
        PENUMBRA_TRY(apply_enum(lb, lp, "lookup", s.light_buffer.lookup));
    }
    if (j.contains("scattering")) {
        const json& sc = j.at("scattering");
        const std::string cp = p + "/scattering";
        PENUMBRA_TRY(expect_object(sc, cp));
        PENUMBRA_TRY(only_fields_and_settings(sc, cp, {}));
        PENUMBRA_TRY(apply_table_settings(sc, cp, request));
    }
    return base::Ok{};
}

base::Status apply_output(const json& j, const std::string& p, OutputOptions& output) {
    PENUMBRA_TRY(expect_object(j, p));
    PENUMBRA_TRY(only_fields(j, p, {"encoding", "jpeg_quality"}));
    PENUMBRA_TRY(apply_enum(j, p, "encoding", output.encoding, encode::frame_format_named,
                            encode::frame_format_names(", ", " or ")));
    PENUMBRA_TRY(optional_member(j, p, "jpeg_quality", output.jpeg_quality,
                                 whole_in(kJpegQualityRange)));
    return base::Ok{};
}

json vec3_json(glm::dvec3 v) {
    return json::array({v.x, v.y, v.z});
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

base::Status apply_patch(std::string_view patch_json, SessionState& state, const Limits& limits) {
    auto patch = parse_patch(patch_json, limits);
    if (!patch) {
        return patch.error();
    }
    return apply_patch(*patch, state, limits);
}

base::Status apply_patch(const Patch& parsed, SessionState& state, const Limits& limits) {
    const json& patch = parsed.document().object;
    PENUMBRA_TRY(
            only_fields(patch, "", {"camera", "light", "transfer_function", "settings", "output"}));
    SessionState next = state;
    if (patch.contains("camera")) {
        PENUMBRA_TRY(apply_camera(patch.at("camera"), "/camera", next.frame));
    }
    if (patch.contains("light")) {
        PENUMBRA_TRY(apply_light(patch.at("light"), "/light", next.frame));
    }
    if (patch.contains("transfer_function")) {
        auto tf = transfer_function_from(patch.at("transfer_function"), "/transfer_function",
                                         std::nullopt);
        if (!tf) {
            return tf.error();
        }
        next.frame.transfer_function = std::move(tf.value());
    }
    if (patch.contains("settings")) {
        PENUMBRA_TRY(apply_settings(patch.at("settings"), "/settings", next.frame,
                                    next.frame_budget_ms, next.refinement_steps, limits));
    }
    if (patch.contains("output")) {
        PENUMBRA_TRY(apply_output(patch.at("output"), "/output", next.output));
    }
    if (auto status = scene::validate(next.frame, scene_limits(limits)); !status) {
        // scene names fields with dots ("camera", "light.direction", "light_buffer.slices"); as
        // a pointer into the patch: "/camera", "/light/direction", "/settings/light_buffer/slices".
        const std::string& where = status.error().where;
        const auto is_part = [&](std::string_view part) {
            return where == part || where.starts_with(std::string(part) + ".");
        };
        const bool settings =
                !is_part("camera") && !is_part("light") && !is_part("transfer_function");
        std::string pointer = (settings ? "/settings/" : "/") + where;
        std::replace(pointer.begin(), pointer.end(), '.', '/');
        return field_error("invalid_value", pointer, status.error().message);
    }
    state = std::move(next);
    return base::Ok{};
}

namespace json_fields {

json transfer_function_json(const scene::TransferFunction& tf) {
    json colors = json::array();
    for (const auto& c : tf.colors) {
        colors.push_back({{"x", c.x}, {"rgb", vec3_json(c.rgb)}});
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

}  // namespace json_fields

std::string state_to_json(const SessionState& state) {
    const scene::FrameRequest& f = state.frame;
    const scene::RenderSettings& s = f.settings;
    json out = {
            {"camera",
             {{"eye", vec3_json(f.camera.eye)},
              {"target", vec3_json(f.camera.target)},
              {"up", vec3_json(f.camera.up)}}},
            {"light",
             {{"type", scene::to_string(f.light.type)},
              {"direction", vec3_json(f.light.direction)},
              {"position", vec3_json(f.light.position)},
              {"color", vec3_json(f.light.color)}}},
            {"transfer_function", transfer_function_json(f.transfer_function)},
            {"settings",
             {{"mode", scene::to_string(s.mode)},
              {"compositing", scene::to_string(s.compositing)},
              {"stage", scene::to_string(s.stage)},
              {"size", json::array({s.width, s.height})},
              {"background", vec3_json(s.background)},
              {"phong", s.phong},
              {"empty_space_skipping", s.empty_space_skipping},
              {"jitter", s.jitter},
              {"frame_budget_ms", state.frame_budget_ms},
              {"refinement_steps", state.refinement_steps},
              {"light_buffer",
               {{"slices", s.light_buffer.slices},
                {"resolution", s.light_buffer.resolution},
                {"builder", scene::to_string(s.light_buffer.builder)},
                {"lookup", scene::to_string(s.light_buffer.lookup)}}}}},
            {"output",
             {{"encoding", encode::to_string(state.output.encoding)},
              {"jpeg_quality", state.output.jpeg_quality}}},
    };
    // The table's settings that a request holds, each at its path.
    for (const scene::SettingRange* range : scene::kSettingRanges) {
        if (range->read == nullptr) {
            continue;
        }
        const double value = range->read(f);
        json& member = out[json::json_pointer(pointer_of(*range))];
        member = range->integer ? json(static_cast<int>(value)) : json(value);
    }
    return out.dump();
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
