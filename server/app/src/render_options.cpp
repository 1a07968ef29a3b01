#include "render_options.hpp"

#include "transfer_function_file.hpp"

#include <penumbra/scene/camera.hpp>
#include <penumbra/scene/default_preset.hpp>

#include <cstdio>
#include <string>
#include <utility>

namespace penumbra::app {

namespace {

// The settings of the table that a request holds: each has an option named by option_name.
bool is_numeric_option(const scene::SettingRange& range) {
    return range.write != nullptr;
}

}  // namespace

const std::vector<std::string>& frame_option_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> all = {
                "mode",  "size",       "camera",         "view",        "eye",     "target",
                "up",    "light",      "light-position", "light-color", "tf",      "compositing",
                "stage", "background", "slices",         "light-res",   "builder", "light-lookup",
        };
        for (const scene::SettingRange* range : scene::kSettingRanges) {
            if (is_numeric_option(*range)) {
                all.push_back(scene::option_name(*range));
            }
        }
        return all;
    }();
    return names;
}

std::string modes_help() {
    std::string help;
    for (const scene::ModeInfo& mode : scene::modes()) {
        char line[160];
        std::snprintf(line, sizeof line, "      %-12s %.*s\n", mode.name.data(),
                      static_cast<int>(mode.summary.size()), mode.summary.data());
        help += line;
    }
    return help;
}

const std::vector<std::string>& frame_flag_names() {
    static const std::vector<std::string> names = {"phong", "no-empty-space-skipping", "jitter"};
    return names;
}

// One entry per numeric setting: its option, what it does, its range and its default.
std::string numeric_options_help() {
    const scene::FrameRequest defaults;
    std::string help;
    for (const scene::SettingRange* range : scene::kSettingRanges) {
        if (!is_numeric_option(*range)) {
            continue;
        }
        const std::string option = scene::option_name(*range) + (range->integer ? " N" : " X");
        char line[256];
        std::snprintf(line, sizeof line, "  --%-28s %.*s\n%33s%s, default %g\n", option.c_str(),
                      static_cast<int>(range->summary.size()), range->summary.data(), "",
                      range->describe().c_str(), range->read(defaults));
        help += line;
    }
    return help;
}

const char* frame_options_help() {
    static const std::string help =
            "  --mode MODE                    (default phong)\n" + modes_help() +
            "  --phong                        Blinn-Phong on top of shadows (shadow modes)\n"
            "  --no-empty-space-skipping      sample the bricks the TF leaves transparent too\n"
            "                                 (the same image, slower)\n"
            "  --jitter                       ray-cast modes: per-pixel jittered sample offsets\n"
            "                                 (fine noise instead of fixed-step rings)\n"
            "  --slices N                     light slices, also half-angle's slices (default "
            "128)\n"
            "  --light-res R                  light buffer R x R texels (default 256)\n"
            "  --builder per_slice|multi_slice  light-buffer builder (default multi_slice)\n"
            "  --light-lookup local|interpolate  camera samples read the light buffer: the layer\n"
            "                                 nearer the light + a march through the rest of\n"
            "                                 the slab (default), or the paper's interpolation\n"
            "                                 between the two nearest layers\n"
            "  --size WxH                     image size (default 512x512)\n"
            "  --camera AZ,EL,DIST            orbit camera: azimuth and elevation in degrees "
            "about\n"
            "                                 the volume centre (z up, azimuth 0 = +y), distance "
            "in\n"
            "                                 units of the volume's longest side\n"
            "  --view SIDE                    the view from that side of the patient: anterior\n"
            "                                 (the default: the face, superior up), posterior,\n"
            "                                 left, right (superior up), superior, inferior\n"
            "                                 (anterior up); world space is RAS\n"
            "  --eye X,Y,Z --target X,Y,Z --up X,Y,Z   explicit camera instead of --camera\n"
            "  --light AZ,EL                  directional light from these angles (default 10,45)\n"
            "  --light-position X,Y,Z         point light at this position instead\n"
            "  --light-color R,G,B            (default 1,1,1)\n"
            "  --tf PRESET|FILE.json          transfer function (default mri_skin, on a CT in HU\n"
            "                                 ct_bone); presets:\n"
            "                                 grey_ramp mri_skin mri_brain, in HU: ct_bone\n"
            "                                 ct_skin ct_soft_tissue ct_lung ct_angio\n"
            "  --compositing alpha|extinction (default alpha)\n"
            "  --stage compute|fragment       where the ray caster runs (default compute)\n"
            "  --background R,G,B             (default 0,0,0)\n" +
            numeric_options_help();
    return help.c_str();
}

base::Result<scene::FrameRequest> frame_request_from(const Arguments& args,
                                                     const volume::Volume& volume) {
    scene::FrameRequest request;
    scene::RenderSettings& s = request.settings;
    s.mode = scene::Mode::phong;
    if (const auto mode = args.get("mode")) {
        const auto parsed = scene::parse_mode(*mode);
        if (!parsed) {
            return base::make_error("invalid_argument",
                                    "unknown mode '" + *mode + "' (" + scene::mode_names() + ")",
                                    "--mode");
        }
        s.mode = *parsed;
    }
    auto size = args.size("size", {512, 512});
    if (!size) {
        return size.error();
    }
    s.width = size->first;
    s.height = size->second;

    const bool explicit_camera = args.has("eye") || args.has("target") || args.has("up");
    if (int(explicit_camera) + int(args.has("camera")) + int(args.has("view")) > 1) {
        return base::make_error("invalid_argument",
                                "give one of --view, --camera and --eye/--target/--up", "--view");
    }
    if (explicit_camera) {
        auto eye = args.vec3("eye", request.camera.eye);
        auto target = args.vec3("target", request.camera.target);
        auto up = args.vec3("up", request.camera.up);
        if (!eye || !target || !up) {
            return !eye ? eye.error() : !target ? target.error() : up.error();
        }
        request.camera.eye = *eye;
        request.camera.target = *target;
        request.camera.up = *up;
    } else if (args.has("camera")) {
        auto orbit = args.vec3("camera", {});
        if (!orbit) {
            return orbit.error();
        }
        request.camera = scene::orbit_camera(orbit->x, orbit->y, orbit->z);
    } else if (const auto name = args.get("view")) {
        const auto view = scene::parse_view(*name);
        if (!view) {
            return base::make_error("invalid_argument",
                                    "unknown view '" + *name + "' (" + scene::view_names() + ")",
                                    "--view");
        }
        request.camera = scene::view_camera(*view);
    }
    scene::Light& light = request.light;
    if (args.has("light-position")) {
        auto position = args.vec3("light-position", {});
        if (!position) {
            return position.error();
        }
        light.type = scene::LightType::point;
        light.position = *position;
    } else {
        auto numbers = parse_numbers(args.get("light").value_or("10,45"), "light");
        if (!numbers) {
            return numbers.error();
        }
        if (numbers->size() != 2) {
            return base::make_error("invalid_argument", "expects AZIMUTH,ELEVATION in degrees",
                                    "--light");
        }
        light.direction = scene::direction_from_angles((*numbers)[0], (*numbers)[1]);
    }
    auto color = args.vec3("light-color", light.color);
    auto background = args.vec3("background", s.background);
    if (!color || !background) {
        return !color ? color.error() : background.error();
    }
    light.color = *color;
    s.background = *background;

    // Each numeric setting from its option, within its range (scene::setting), errors named by
    // the option.
    for (const scene::SettingRange* range : scene::kSettingRanges) {
        if (!is_numeric_option(*range)) {
            continue;
        }
        const std::string option = scene::option_name(*range);
        const double current = range->read(request);
        double value = current;
        if (range->integer) {
            auto whole = args.integer(option, static_cast<int>(current));
            if (!whole) {
                return whole.error();
            }
            value = *whole;
        } else {
            auto number = args.number(option, current);
            if (!number) {
                return number.error();
            }
            value = *number;
        }
        if (!range->contains(value)) {
            return base::make_error("invalid_argument", "must be " + range->describe(),
                                    "--" + option);
        }
        range->write(request, value);
    }
    // Bounded by the device (scene::Limits), which validate checks.
    for (const auto& [option, target] : {std::pair{"slices", &s.light_buffer.slices},
                                         std::pair{"light-res", &s.light_buffer.resolution}}) {
        auto value = args.integer(option, *target);
        if (!value) {
            return value.error();
        }
        *target = *value;
    }
    s.phong = args.has("phong");
    s.empty_space_skipping = !args.has("no-empty-space-skipping");
    s.jitter = args.has("jitter");
    if (const auto builder = args.get("builder")) {
        const auto parsed = scene::parse_light_buffer_builder(*builder);
        if (!parsed) {
            return base::make_error("invalid_argument", "expects per_slice or multi_slice",
                                    "--builder");
        }
        s.light_buffer.builder = *parsed;
    }
    if (const auto lookup = args.get("light-lookup")) {
        const auto parsed = scene::parse_light_lookup(*lookup);
        if (!parsed) {
            return base::make_error("invalid_argument", "expects local or interpolate",
                                    "--light-lookup");
        }
        s.light_buffer.lookup = *parsed;
    }
    if (const auto compositing = args.get("compositing")) {
        const auto parsed = scene::parse_compositing(*compositing);
        if (!parsed) {
            return base::make_error("invalid_argument", "expects alpha or extinction",
                                    "--compositing");
        }
        s.compositing = *parsed;
    }
    if (const auto stage = args.get("stage")) {
        const auto parsed = scene::parse_raycast_stage(*stage);
        if (!parsed) {
            return base::make_error("invalid_argument", "expects compute or fragment", "--stage");
        }
        s.stage = *parsed;
    }
    auto tf = load_transfer_function(
            args.get("tf").value_or(std::string(scene::default_preset(volume.hounsfield))),
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

}  // namespace penumbra::app
