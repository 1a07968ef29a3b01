#include "render_options.hpp"

#include "transfer_function_file.hpp"

#include <penumbra/scene/camera.hpp>

namespace penumbra::app {

const std::vector<std::string>& frame_option_names() {
    static const std::vector<std::string> names = {"mode",
                                                   "size",
                                                   "camera",
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

const std::vector<std::string>& frame_flag_names() {
    static const std::vector<std::string> names = {"phong"};
    return names;
}

const char* frame_options_help() {
    return "  --mode MODE                    dvr | phong | half_angle | sbrc | sbrc_shell | "
           "sbrc_cone |\n"
           "                                 reference (default phong)\n"
           "  --phong                        Blinn-Phong on top of shadows (shadow modes)\n"
           "  --slices N                     light slices, also half-angle's slices (default 128)\n"
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
           "  --camera AZ,EL,DIST            orbit camera: azimuth and elevation in degrees about\n"
           "                                 the volume centre (z up, azimuth 0 = +y), distance "
           "in\n"
           "                                 units of the volume's longest side (default "
           "25,10,2.6)\n"
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
                                    "unknown mode '" + *mode +
                                            "' (dvr, phong, half_angle, sbrc, sbrc_shell, "
                                            "sbrc_cone, reference)",
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

    if (args.has("eye") || args.has("target") || args.has("up")) {
        auto eye = args.vec3("eye", request.camera.eye);
        auto target = args.vec3("target", request.camera.target);
        auto up = args.vec3("up", request.camera.up);
        if (!eye || !target || !up) {
            return !eye ? eye.error() : !target ? target.error() : up.error();
        }
        request.camera.eye = *eye;
        request.camera.target = *target;
        request.camera.up = *up;
    } else {
        auto orbit = args.vec3("camera", {25.0, 10.0, 2.6});
        if (!orbit) {
            return orbit.error();
        }
        request.camera = scene::orbit_camera(orbit->x, orbit->y, orbit->z);
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

    struct NumberOption {
        const char* name;
        double* target;
    };

    const NumberOption numbers[] = {
            {"intensity", &light.intensity},
            {"ambient", &light.ambient},
            {"diffuse", &s.shading.diffuse},
            {"specular", &s.shading.specular},
            {"shininess", &s.shading.shininess},
            {"sample-distance", &s.sample_distance},
            {"opacity-unit", &s.opacity_unit_distance},
            {"early-termination", &s.early_termination},
            {"compensation", &s.light_buffer.compensation},
            {"shell-radius", &s.scattering.shell_radius},
            {"shell-weight", &s.scattering.shell_center_weight},
            {"cone-angle", &s.scattering.cone_angle_degrees},
            {"cone-weight", &s.scattering.cone_center_weight},
    };
    for (const auto& option : numbers) {
        auto value = args.number(option.name, *option.target);
        if (!value) {
            return value.error();
        }
        *option.target = *value;
    }

    struct IntegerOption {
        const char* name;
        int* target;
    };

    const IntegerOption integers[] = {
            {"slices", &s.light_buffer.slices},
            {"light-res", &s.light_buffer.resolution},
            {"shell-rings", &s.scattering.shell_rings},
            {"slab-samples", &s.light_buffer.slab_samples},
    };
    for (const auto& option : integers) {
        auto value = args.integer(option.name, *option.target);
        if (!value) {
            return value.error();
        }
        *option.target = *value;
    }
    s.phong = args.has("phong");
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
