#include "render_options.hpp"

#include "transfer_function_file.hpp"

#include <penumbra/scene/camera.hpp>

#include <cstdio>
#include <string>

namespace penumbra::app {

const std::vector<std::string>& frame_option_names() {
    static const std::vector<std::string> names = {"mode",
                                                   "size",
                                                   "camera",
                                                   "view",
                                                   "eye",
                                                   "target",
                                                   "up",
                                                   "fov",
                                                   "light",
                                                   "light-position",
                                                   "light-color",
                                                   "intensity",
                                                   "ambient",
                                                   "diffuse",
                                                   "specular",
                                                   "shininess",
                                                   "tf",
                                                   "sample-distance",
                                                   "opacity-unit",
                                                   "compositing",
                                                   "stage",
                                                   "background",
                                                   "early-termination",
                                                   "slices",
                                                   "light-res",
                                                   "builder",
                                                   "compensation",
                                                   "slab-samples",
                                                   "light-lookup",
                                                   "shell-radius",
                                                   "shell-rings",
                                                   "shell-weight",
                                                   "cone-angle",
                                                   "cone-weight"};
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
            "  --compensation N               darkening compensation (1+alpha)^N, 0 = off\n"
            "  --light-lookup local|interpolate  camera samples read the light buffer: the layer\n"
            "                                 nearer the light + a march through the rest of\n"
            "                                 the slab (default), or the paper's interpolation\n"
            "                                 between the two nearest layers\n"
            "  --slab-samples K               points per light slab: 1 = the slice plane only\n"
            "                                 (the paper), 0 = one per voxel (default 0)\n"
            "  --shell-radius D --shell-rings K --shell-weight W   sbrc_shell (2/256, 1, 0.4)\n"
            "  --cone-angle DEG --cone-weight W                    sbrc_cone (30, 0.2)\n"
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
            "  --fov DEG                      vertical field of view (default 30)\n"
            "  --light AZ,EL                  directional light from these angles (default 10,45)\n"
            "  --light-position X,Y,Z         point light at this position instead\n"
            "  --light-color R,G,B --intensity I --ambient A   (defaults 1,1,1  1  0.25)\n"
            "  --diffuse KD --specular KS --shininess N        Blinn-Phong (0.75 0.3 32)\n"
            "  --tf PRESET|FILE.json          transfer function (default mri_skin); presets:\n"
            "                                 grey_ramp mri_skin mri_brain, in HU: ct_bone\n"
            "                                 ct_skin ct_soft_tissue ct_lung ct_angio\n"
            "  --sample-distance D            ray step, unit = longest side (default 1/256)\n"
            "  --opacity-unit D               distance the TF opacity refers to (default 1/256)\n"
            "  --compositing alpha|extinction (default alpha)\n"
            "  --stage compute|fragment       where the ray caster runs (default compute)\n"
            "  --background R,G,B             (default 0,0,0)\n"
            "  --early-termination A          stop rays at this opacity (default 0.99)\n";
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
    auto fov = args.number("fov", 30.0);
    if (!fov) {
        return fov.error();
    }
    request.camera.fov_y_degrees = *fov;

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

    // Each option's limits are its setting's (scene::setting), named by the option.
    const auto out_of_range = [](const char* option, const scene::SettingRange& range) {
        return base::make_error("invalid_argument", "must be " + range.describe(),
                                std::string("--") + option);
    };

    struct NumberOption {
        const char* name;
        double* target;
        const scene::SettingRange& range;
    };

    const NumberOption numbers[] = {
            {"intensity", &light.intensity, scene::setting::light_intensity},
            {"ambient", &light.ambient, scene::setting::light_ambient},
            {"diffuse", &s.shading.diffuse, scene::setting::diffuse},
            {"specular", &s.shading.specular, scene::setting::specular},
            {"shininess", &s.shading.shininess, scene::setting::shininess},
            {"sample-distance", &s.sample_distance, scene::setting::sample_distance},
            {"opacity-unit", &s.opacity_unit_distance, scene::setting::opacity_unit_distance},
            {"early-termination", &s.early_termination, scene::setting::early_termination},
            {"compensation", &s.light_buffer.compensation, scene::setting::compensation},
            {"shell-radius", &s.scattering.shell_radius, scene::setting::shell_radius},
            {"shell-weight", &s.scattering.shell_center_weight,
             scene::setting::shell_center_weight},
            {"cone-angle", &s.scattering.cone_angle_degrees, scene::setting::cone_angle_degrees},
            {"cone-weight", &s.scattering.cone_center_weight, scene::setting::cone_center_weight},
    };
    for (const auto& option : numbers) {
        auto value = args.number(option.name, *option.target);
        if (!value) {
            return value.error();
        }
        if (!option.range.contains(*value)) {
            return out_of_range(option.name, option.range);
        }
        *option.target = *value;
    }

    struct IntegerOption {
        const char* name;
        int* target;
        const scene::SettingRange* range;  // null: bounded by the device (scene::Limits)
    };

    const IntegerOption integers[] = {
            {"slices", &s.light_buffer.slices, nullptr},
            {"light-res", &s.light_buffer.resolution, nullptr},
            {"shell-rings", &s.scattering.shell_rings, &scene::setting::shell_rings},
            {"slab-samples", &s.light_buffer.slab_samples, &scene::setting::slab_samples},
    };
    for (const auto& option : integers) {
        auto value = args.integer(option.name, *option.target);
        if (!value) {
            return value.error();
        }
        if (option.range != nullptr && !option.range->contains(*value)) {
            return out_of_range(option.name, *option.range);
        }
        *option.target = *value;
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
    auto tf = load_transfer_function(args.get("tf").value_or("mri_skin"), volume.range);
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
