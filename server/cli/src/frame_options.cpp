#include "penumbra/cli/frame_options.hpp"

#include <penumbra/base/text.hpp>
#include <penumbra/cli/transfer_function_file.hpp>
#include <penumbra/scene/camera.hpp>
#include <penumbra/scene/default_preset.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::cli {

namespace {

// The rows of scene's table that the command line sets with an option of their own.
bool has_option(const scene::Setting& setting) {
    return setting.in_frame() && setting.command_line == scene::CommandLine::option;
}

// A boolean that is on until said otherwise is turned off by `--no-<name>`.
bool is_negated(const scene::Setting& setting, const scene::FrameRequest& defaults) {
    return setting.kind == scene::SettingKind::boolean && setting.read_frame(defaults).x != 0.0;
}

std::string option_of(const scene::Setting& setting, const scene::FrameRequest& defaults) {
    return (is_negated(setting, defaults) ? "no-" : "") + scene::option_name(setting);
}

// The frame the command line starts from: a new request's, shaded with Blinn-Phong; a still's
// samples jittered.
scene::FrameRequest command_line_defaults(FramePurpose purpose) {
    scene::FrameRequest request;
    request.settings.mode = scene::Mode::phong;
    switch (purpose) {
        case FramePurpose::measurement:
            break;
        case FramePurpose::still:
            request.settings.jitter = true;
            break;
    }
    return request;
}

// The help line of a setting: its summary, its range where no device bounds it, and for a choice
// whose values say what they do, one line each.
std::string help_of(const scene::Setting& setting, const scene::FrameRequest& defaults) {
    std::string help(setting.summary);
    if (is_negated(setting, defaults)) {
        help = "turn off: " + help;
    }
    const bool ranged =
            setting.kind == scene::SettingKind::number || setting.kind == scene::SettingKind::whole;
    if (ranged && setting.limit == nullptr) {
        help += "; " + setting.describe();
    }
    for (std::size_t i = 0; i < setting.choice_summaries.size(); ++i) {
        char line[160];
        std::snprintf(line, sizeof line, "\n  %-12s \t%.*s", setting.choices[i].data(),
                      static_cast<int>(setting.choice_summaries[i].size()),
                      setting.choice_summaries[i].data());
        help += line;
    }
    return help;
}

// The option's value, with the default the command line starts from.
po::value_semantic* value_of(const scene::Setting& setting, const scene::FrameRequest& defaults) {
    const scene::SettingValue fallback = setting.read_frame(defaults);
    switch (setting.kind) {
        case scene::SettingKind::number:
            return po::value<Number>()->value_name("X")->default_value({fallback.x});
        case scene::SettingKind::whole:
            return po::value<int>()->value_name("N")->default_value(static_cast<int>(fallback.x));
        case scene::SettingKind::boolean:
            return new po::untyped_value(true);
        case scene::SettingKind::choice:
            return po::value<std::string>()
                    ->value_name(scene::choice_list(setting, "|", "|"))
                    ->default_value(
                            std::string(setting.choices[static_cast<std::size_t>(fallback.x)]));
        case scene::SettingKind::vector:
            return po::value<Triple>()
                    ->value_name(setting.min >= 0.0 ? "R,G,B" : "X,Y,Z")
                    ->default_value({fallback});
        case scene::SettingKind::size:
            return po::value<ImageSize>()->value_name("WxH")->default_value(
                    {static_cast<int>(fallback.x), static_cast<int>(fallback.y)});
    }
    return nullptr;
}

// The value an option gives a setting; none where the option is not given.
base::Result<std::optional<scene::SettingValue>> given_value(const po::variables_map& options,
                                                             const scene::Setting& setting,
                                                             const scene::FrameRequest& defaults) {
    const std::string option = option_of(setting, defaults);
    if (setting.kind == scene::SettingKind::boolean) {
        // A flag: given, it says the opposite of the default.
        const bool given = options.count(option) != 0;
        return std::optional(scene::SettingValue(given != is_negated(setting, defaults), 0, 0));
    }
    if (options.count(option) == 0) {
        return std::optional<scene::SettingValue>();
    }
    const po::variable_value& given = options[option];
    switch (setting.kind) {
        case scene::SettingKind::number:
            return std::optional(scene::SettingValue(given.as<Number>().value, 0, 0));
        case scene::SettingKind::whole:
            return std::optional(scene::SettingValue(given.as<int>(), 0, 0));
        case scene::SettingKind::boolean:
            break;
        case scene::SettingKind::choice: {
            const std::string& text = given.as<std::string>();
            const auto& names = setting.choices;
            const auto found = std::find(names.begin(), names.end(), text);
            if (found == names.end()) {
                return base::make_error(base::ErrorCode::invalid_argument,
                                        "expects " + scene::choice_list(setting, ", ", " or "),
                                        "--" + option);
            }
            return std::optional(
                    scene::SettingValue(static_cast<double>(found - names.begin()), 0, 0));
        }
        case scene::SettingKind::vector:
            return std::optional(given.as<Triple>().value);
        case scene::SettingKind::size: {
            const auto size = given.as<ImageSize>();
            return std::optional(scene::SettingValue(size.width, size.height, 0));
        }
    }
    return std::optional<scene::SettingValue>();
}

// The defaults and the presets, normalised then in HU, from scene's lists.
std::string tf_help() {
    const std::vector<std::string> hu = scene::hounsfield_preset_names();
    std::string normalised;
    std::string in_hu;
    for (const std::string& name : scene::preset_names()) {
        std::string& list = std::find(hu.begin(), hu.end(), name) == hu.end() ? normalised : in_hu;
        list += (list.empty() ? "" : " ") + name;
    }
    return "transfer function (default " + std::string(scene::kDefaultPreset) + ", on a CT in HU " +
           std::string(scene::kDefaultHounsfieldPreset) + "); presets: " + normalised +
           ", in HU: " + in_hu;
}

template <class T>
std::optional<T> value_of(const po::variables_map& options, const char* name) {
    return options.count(name) != 0 ? std::optional<T>(options[name].as<T>()) : std::nullopt;
}

base::Status read_camera(const po::variables_map& options, scene::Camera& camera) {
    const bool explicit_camera =
            options.count("eye") + options.count("target") + options.count("up") > 0;
    if (int(explicit_camera) + options.count("camera") + options.count("view") > 1) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "give one of --view, --camera and --eye/--target/--up", "--view");
    }
    if (explicit_camera) {
        camera.eye = value_of<Triple>(options, "eye").value_or(Triple{camera.eye}).value;
        camera.target = value_of<Triple>(options, "target").value_or(Triple{camera.target}).value;
        camera.up = value_of<Triple>(options, "up").value_or(Triple{camera.up}).value;
    } else if (const auto orbit = value_of<Triple>(options, "camera")) {
        camera = scene::orbit_camera(orbit->value.x, orbit->value.y, orbit->value.z);
    } else if (const auto name = value_of<std::string>(options, "view")) {
        const auto view = scene::parse_name<scene::View>(*name);
        if (!view) {
            return base::make_error(
                    base::ErrorCode::invalid_argument,
                    "unknown view '" + *name + "' (" + scene::name_list<scene::View>(", ") + ")",
                    "--view");
        }
        camera = scene::view_camera(*view);
    }
    return base::Ok{};
}

base::Status read_light(const po::variables_map& options, scene::Light& light) {
    if (const auto position = value_of<Triple>(options, "light-position")) {
        light.type = scene::LightType::point;
        light.position = position->value;
    } else if (const auto angles = value_of<std::string>(options, "light")) {
        auto numbers = base::parse_numbers(*angles, "--light");
        if (!numbers) {
            return numbers.error();
        }
        if (numbers->size() != 2) {
            return base::make_error(base::ErrorCode::invalid_argument,
                                    "expects AZIMUTH,ELEVATION in degrees", "--light");
        }
        light.direction = scene::direction_from_angles((*numbers)[0], (*numbers)[1]);
    }
    return base::Ok{};
}

// Whether each component of `value` is one `row` may take; the error names the option.
base::Status check_components(const scene::Setting& row, glm::dvec3 value,
                              const std::string& option) {
    if (!scene::validate_value(row, value, scene::Limits{})) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "must be " + row.describe() + " in each component", option);
    }
    return base::Ok{};
}

// The crop box, as X0,X1,Y0,Y1,Z0,Z1 in RAS millimetres: each axis's range, as Slicer's ROI and
// VolView's crop read. The order within an axis does not matter; an empty range is validate's.
base::Status read_crop(const po::variables_map& options, scene::Cut& cut) {
    const auto text = value_of<std::string>(options, "crop");
    if (!text) {
        return base::Ok{};
    }
    auto numbers = base::parse_numbers(*text, "--crop");
    if (!numbers) {
        return numbers.error();
    }
    if (numbers->size() != 6) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "expects X0,X1,Y0,Y1,Z0,Z1 in RAS millimetres", "--crop");
    }
    const auto& n = *numbers;
    const glm::dvec3 a(n[0], n[2], n[4]);
    const glm::dvec3 b(n[1], n[3], n[5]);
    for (const glm::dvec3& corner : {a, b}) {
        if (auto status = check_components(scene::setting::crop_min, corner, "--crop"); !status) {
            return status;
        }
    }
    cut.crop = {true, glm::min(a, b), glm::max(a, b)};
    return base::Ok{};
}

// Each --clip-plane PX,PY,PZ,NX,NY,NZ (RAS millimetres; the normal toward the side kept, any
// length but zero) fills the next of the cut's planes.
base::Status read_clip_planes(const po::variables_map& options, scene::Cut& cut) {
    const auto texts = value_of<std::vector<std::string>>(options, "clip-plane");
    if (!texts) {
        return base::Ok{};
    }
    if (texts->size() > cut.planes.size()) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "at most " + std::to_string(cut.planes.size()) + " clip planes",
                                "--clip-plane");
    }
    for (std::size_t i = 0; i < texts->size(); ++i) {
        auto numbers = base::parse_numbers((*texts)[i], "--clip-plane");
        if (!numbers) {
            return numbers.error();
        }
        if (numbers->size() != 6) {
            return base::make_error(base::ErrorCode::invalid_argument,
                                    "expects PX,PY,PZ,NX,NY,NZ: a point in RAS millimetres and "
                                    "the normal toward the side kept",
                                    "--clip-plane");
        }
        const auto& n = *numbers;
        const glm::dvec3 point(n[0], n[1], n[2]);
        const glm::dvec3 normal(n[3], n[4], n[5]);
        const double length = glm::length(normal);
        if (!(length > 1e-9) || !std::isfinite(length)) {
            return base::make_error(base::ErrorCode::invalid_argument,
                                    "the normal must be finite and not zero", "--clip-plane");
        }
        // A plane's point ranges as the crop box's corners.
        if (auto status = check_components(scene::setting::crop_min, point, "--clip-plane");
            !status) {
            return status;
        }
        cut.planes[i] = {true, point, normal / length};
    }
    return base::Ok{};
}

base::Status read_cut(const po::variables_map& options, scene::Cut& cut) {
    if (auto status = read_crop(options, cut); !status) {
        return status;
    }
    return read_clip_planes(options, cut);
}

// Each setting of the table from its option, within its range; errors name the option. The
// device's bounds (image size, slices, light-buffer resolution) are validate's to check.
base::Status read_settings(const po::variables_map& options, FramePurpose purpose,
                           scene::FrameRequest& request) {
    const scene::FrameRequest defaults = command_line_defaults(purpose);
    scene::State state;
    state.frame = std::move(request);
    for (const scene::Setting* setting : scene::kSettings) {
        if (!has_option(*setting)) {
            continue;
        }
        auto value = given_value(options, *setting, defaults);
        if (!value) {
            return value.error();
        }
        if (!*value) {
            continue;
        }
        if (setting->limit == nullptr) {
            if (auto within = scene::validate_value(*setting, **value, scene::Limits{}); !within) {
                return base::make_error(
                        base::ErrorCode::invalid_argument,
                        "must be " + setting->describe() +
                                (setting->kind == scene::SettingKind::vector ? " in each component"
                                                                             : ""),
                        "--" + option_of(*setting, defaults));
            }
        }
        setting->write(state, **value);
    }
    request = std::move(state.frame);
    return base::Ok{};
}

}  // namespace

po::options_description frame_options(const std::vector<std::string>& swept, FramePurpose purpose) {
    const scene::FrameRequest defaults = command_line_defaults(purpose);
    po::options_description options = option_group("frame options");
    const auto add = [&](const std::string& name, const po::value_semantic* value,
                         const std::string& help) {
        if (std::find(swept.begin(), swept.end(), name) == swept.end()) {
            options.add(boost::shared_ptr<po::option_description>(
                    new po::option_description(name.c_str(), value, help.c_str())));
        } else {
            delete value;
        }
    };
    const auto text = [](const std::string& name, const std::string& fallback = {}) {
        auto* value = po::value<std::string>()->value_name(name);
        return fallback.empty() ? value : value->default_value(fallback);
    };
    const auto triple = [](const char* name) { return po::value<Triple>()->value_name(name); };
    add("camera", triple("AZ,EL,DIST"),
        "orbit camera: azimuth and elevation in degrees about the volume centre (z up, azimuth 0 "
        "= +y), distance in units of the volume's longest side");
    add("view", text("SIDE"),
        "the view from that side of the patient (world space is RAS): anterior (the default: "
        "the face, superior up), posterior, left, right (superior up), superior, inferior "
        "(anterior up)");
    add("eye", triple("X,Y,Z"), "explicit camera instead of --camera, with --target and --up");
    add("target", triple("X,Y,Z"), "the point the explicit camera looks at");
    add("up", triple("X,Y,Z"), "the explicit camera's up direction");
    add("light", text("AZ,EL", "10,45"), "directional light from these angles in degrees");
    add("light-position", triple("X,Y,Z"), "point light at this position instead");
    add("tf", text("PRESET|FILE.json"), tf_help());
    add("crop", text("X0,X1,Y0,Y1,Z0,Z1"),
        "draw only what lies within this box, in patient millimetres (RAS: x toward the "
        "patient's right, y anterior, z superior; penumbra info prints the volume's)");
    options.add_options()(
            "clip-plane",
            po::value<std::vector<std::string>>()->composing()->value_name("PX,PY,PZ,NX,NY,NZ"),
            "cut by the plane through this point (patient millimetres, RAS) with "
            "this normal, keeping the side it points to; up to 6, one option each");
    for (const scene::Setting* setting : scene::kSettings) {
        if (has_option(*setting)) {
            add(option_of(*setting, defaults), value_of(*setting, defaults),
                help_of(*setting, defaults));
        }
    }
    return options;
}

base::Result<scene::FrameRequest> frame_request_from(const po::variables_map& options,
                                                     const volume::Volume& volume,
                                                     FramePurpose purpose) {
    scene::FrameRequest request = command_line_defaults(purpose);
    for (const base::Status& status :
         {read_camera(options, request.camera), read_light(options, request.light),
          read_cut(options, request.cut), read_settings(options, purpose, request)}) {
        if (!status) {
            return status.error();
        }
    }
    auto tf = load_transfer_function(
            value_of<std::string>(options, "tf")
                    .value_or(std::string(scene::default_preset(volume.hounsfield))),
            volume.range);
    if (!tf) {
        return tf.error();
    }
    request.transfer_function = std::move(tf.value());
    if (auto status = scene::validate(request); !status) {
        return status.error();
    }
    return request;
}

base::Result<scene::FrameRequest> default_frame_request(const volume::Volume& volume) {
    auto no_options = parse_options({}, frame_options());
    if (!no_options) {
        return no_options.error();
    }
    return frame_request_from(*no_options, volume);
}

std::vector<std::string> names_of(const SweptOptions& swept) {
    std::vector<std::string> names;
    for (const auto& [name, instead] : swept) {
        names.push_back(name);
    }
    return names;
}

base::Error explain_swept(base::Error error, const SweptOptions& swept, const char* benchmark) {
    for (const auto& [name, instead] : swept) {
        if (error.where == "--" + name) {
            error.message = std::string(benchmark) + " sweeps this; use " + instead;
        }
    }
    return error;
}

}  // namespace penumbra::cli
