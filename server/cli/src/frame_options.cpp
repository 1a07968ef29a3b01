#include "penumbra/cli/frame_options.hpp"

#include <penumbra/base/text.hpp>
#include <penumbra/cli/transfer_function_file.hpp>
#include <penumbra/scene/camera.hpp>
#include <penumbra/scene/default_preset.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::cli {

namespace {

// The settings of the table that a request holds: each has an option named by option_name.
bool is_numeric_option(const scene::SettingRange& range) {
    return range.write != nullptr;
}

// One line per mode: its name and what it does (the mode table's summary).
std::string modes_help() {
    std::string help = "rendering mode:";
    for (const scene::ModeInfo& mode : scene::modes()) {
        char line[160];
        std::snprintf(line, sizeof line, "\n  %-12s \t%.*s", mode.name.data(),
                      static_cast<int>(mode.summary.size()), mode.summary.data());
        help += line;
    }
    return help;
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

// An option naming one of an enum's values, spelled as its scene name table says; `target` keeps
// its value when the option is not given.
template <scene::NamedEnum E>
base::Status read_choice(const po::variables_map& options, const char* name, E& target) {
    if (const auto text = value_of<std::string>(options, name)) {
        const auto parsed = scene::parse_name<E>(*text);
        if (!parsed) {
            return base::make_error("invalid_argument", "expects " + scene::choices<E>(),
                                    std::string("--") + name);
        }
        target = *parsed;
    }
    return base::Ok{};
}

base::Status read_camera(const po::variables_map& options, scene::Camera& camera) {
    const bool explicit_camera =
            options.count("eye") + options.count("target") + options.count("up") > 0;
    if (int(explicit_camera) + options.count("camera") + options.count("view") > 1) {
        return base::make_error("invalid_argument",
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
                    "invalid_argument",
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
            return base::make_error("invalid_argument", "expects AZIMUTH,ELEVATION in degrees",
                                    "--light");
        }
        light.direction = scene::direction_from_angles((*numbers)[0], (*numbers)[1]);
    }
    light.color = options["light-color"].as<Triple>().value;
    return base::Ok{};
}

// Each numeric setting of the table from its option, within its range (scene::setting), errors
// named by the option.
base::Status read_numeric_settings(const po::variables_map& options, scene::FrameRequest& request) {
    for (const scene::SettingRange* range : scene::kSettingRanges) {
        const std::string option = scene::option_name(*range);
        if (!is_numeric_option(*range) || options.count(option) == 0) {
            continue;
        }
        const double value =
                range->integer ? options[option].as<int>() : options[option].as<Number>().value;
        if (!range->contains(value)) {
            return base::make_error("invalid_argument", "must be " + range->describe(),
                                    "--" + option);
        }
        range->write(request, value);
    }
    return base::Ok{};
}

base::Status read_settings(const po::variables_map& options, scene::RenderSettings& s) {
    if (const auto name = value_of<std::string>(options, "mode")) {
        const auto mode = scene::parse_mode(*name);
        if (!mode) {
            return base::make_error("invalid_argument",
                                    "unknown mode '" + *name + "' (" + scene::mode_names() + ")",
                                    "--mode");
        }
        s.mode = *mode;
    }
    const auto size = options["size"].as<ImageSize>();
    s.width = size.width;
    s.height = size.height;
    s.background = options["background"].as<Triple>().value;
    // Bounded by the device (scene::Limits), which validate checks.
    s.light_buffer.slices = value_of<int>(options, "slices").value_or(s.light_buffer.slices);
    s.light_buffer.resolution =
            value_of<int>(options, "light-res").value_or(s.light_buffer.resolution);
    s.phong = options.count("phong") != 0;
    s.empty_space_skipping = options.count("no-empty-space-skipping") == 0;
    s.jitter = options.count("jitter") != 0;
    for (const base::Status& status : {read_choice(options, "builder", s.light_buffer.builder),
                                       read_choice(options, "light-lookup", s.light_buffer.lookup),
                                       read_choice(options, "compositing", s.compositing),
                                       read_choice(options, "stage", s.stage)}) {
        if (!status) {
            return status;
        }
    }
    return base::Ok{};
}

}  // namespace

po::options_description frame_options(const std::vector<std::string>& swept) {
    const scene::FrameRequest defaults;
    const scene::RenderSettings& s = defaults.settings;
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
    // "alpha|extinction", the current value the default.
    const auto choice = [&text](auto value) {
        using Enum = decltype(value);
        return text(scene::name_list<Enum>("|"), scene::to_string(value));
    };
    const auto triple = [](const char* name) { return po::value<Triple>()->value_name(name); };
    add("mode", text("MODE", "phong"), modes_help());
    add("phong", new po::untyped_value(true), "Blinn-Phong on top of shadows (shadow modes)");
    add("no-empty-space-skipping", new po::untyped_value(true),
        "sample the bricks the transfer function leaves transparent too (the same image, slower)");
    add("jitter", new po::untyped_value(true),
        "ray-cast modes: per-pixel jittered sample offsets (fine noise instead of rings)");
    add("size", po::value<ImageSize>()->value_name("WxH")->default_value({512, 512}), "image size");
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
    add("light-color", triple("R,G,B")->default_value({defaults.light.color}), "light colour");
    add("background", triple("R,G,B")->default_value({s.background}), "background colour");
    add("tf", text("PRESET|FILE.json"), tf_help());
    add("compositing", choice(s.compositing), "compositing");
    add("stage", choice(s.stage), "where the ray caster runs");
    add("slices", po::value<int>()->value_name("N")->default_value(s.light_buffer.slices),
        "light slices, also half-angle's slices");
    add("light-res", po::value<int>()->value_name("R")->default_value(s.light_buffer.resolution),
        "light buffer R x R texels");
    add("builder", choice(s.light_buffer.builder), "light-buffer builder");
    add("light-lookup", choice(s.light_buffer.lookup),
        "camera samples read the light buffer: the layer nearer the light + a march through the "
        "rest of the slab (local), or the paper's interpolation between the two nearest layers");
    for (const scene::SettingRange* range : scene::kSettingRanges) {
        if (!is_numeric_option(*range)) {
            continue;
        }
        const std::string help = std::string(range->summary) + "; " + range->describe();
        const double fallback = range->read(defaults);
        add(scene::option_name(*range),
            range->integer
                    ? po::value<int>()->value_name("N")->default_value(int(fallback))
                    : static_cast<po::value_semantic*>(
                              po::value<Number>()->value_name("X")->default_value({fallback})),
            help);
    }
    return options;
}

base::Result<scene::FrameRequest> frame_request_from(const po::variables_map& options,
                                                     const volume::Volume& volume) {
    scene::FrameRequest request;
    request.settings.mode = scene::Mode::phong;
    for (const base::Status& status :
         {read_settings(options, request.settings), read_camera(options, request.camera),
          read_light(options, request.light), read_numeric_settings(options, request)}) {
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
