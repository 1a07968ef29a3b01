#pragma once

#include <penumbra/scene/frame_request.hpp>
#include <penumbra/scene/setting.hpp>
#include <penumbra/scene/state.hpp>

#include <array>
#include <type_traits>
#include <utility>

namespace penumbra::scene {

// A setting of every frame, which `member` picks out of a FrameRequest:
// frame_setting("light/ambient", {.min = 0.0, .max = 1.0, .summary = "ambient light"},
//               [](auto& f) -> auto& { return f.light.ambient; }).
// Its kind follows the member's type; the command line has an option for it unless `spec` says
// otherwise.
template <class Member>
constexpr Setting frame_setting(std::string_view path, SettingSpec spec, Member) {
    using Value = std::remove_cvref_t<decltype(Member{}(std::declval<FrameRequest&>()))>;
    Setting setting = detail::row<Value>(path, spec);
    setting.read = [](const State& s) { return detail::to_value(Member{}(s.frame)); };
    setting.write = [](State& s, SettingValue v) {
        Member{}(s.frame) = detail::from_value<Value>(v);
    };
    setting.read_frame = [](const FrameRequest& f) { return detail::to_value(Member{}(f)); };
    return setting;
}

// A setting of the session that no frame carries, which `member` picks out of a State; the
// command line, which renders single frames, has no option for it.
template <class Member>
constexpr Setting state_setting(std::string_view path, SettingSpec spec, Member) {
    using Value = std::remove_cvref_t<decltype(Member{}(std::declval<State&>()))>;
    spec.command_line = CommandLine::none;
    Setting setting = detail::row<Value>(path, spec);
    setting.read = [](const State& s) { return detail::to_value(Member{}(s)); };
    setting.write = [](State& s, SettingValue v) { Member{}(s) = detail::from_value<Value>(v); };
    return setting;
}

// Every setting a client can set, each declared once. Adding a setting is its member (in
// frame_request.hpp or state.hpp) and its row here, listed in kSettings below. From the row:
// validate checks it; the protocol reads it from a `set` and writes it into every `state`;
// hello announces it; the command line has its option; the shaders see a frame's settings as
// `settings.<path without "settings/", '_' for '/'>` (render's generated Settings block:
// `settings.light_buffer_compensation`, a choice as an int with a define per name,
// SETTINGS_COMPOSITING_EXTINCTION); scripts/update-schema.sh writes its schema, its TypeScript
// type and a new session's value into the web client's generated module.
namespace setting {

// The components of coordinates (the camera, a point light; the volume's longest side is 1) and
// of colours (light, background), which every vector of that kind shares.
inline constexpr Setting coordinate = range_only("vec3", SettingKind::number, -1000.0, 1000.0);
inline constexpr Setting colour = range_only("rgb", SettingKind::number, 0.0, 1.0);

// The camera and the light are placed on the command line by views, orbits and angles.
inline constexpr Setting camera_eye = frame_setting(
        "camera/eye",
        {.min = coordinate.min,
         .max = coordinate.max,
         .summary = "camera position",
         .command_line = CommandLine::by_hand},
        [](auto& f) -> auto& { return f.camera.eye; });
inline constexpr Setting camera_target = frame_setting(
        "camera/target",
        {.min = coordinate.min,
         .max = coordinate.max,
         .summary = "the point the camera looks at",
         .command_line = CommandLine::by_hand},
        [](auto& f) -> auto& { return f.camera.target; });
inline constexpr Setting camera_up = frame_setting(
        "camera/up",
        {.min = coordinate.min,
         .max = coordinate.max,
         .summary = "the camera's up direction",
         .command_line = CommandLine::by_hand},
        [](auto& f) -> auto& { return f.camera.up; });
inline constexpr Setting fov_degrees = frame_setting(
        "camera/fov", {.min = 1.0, .max = 170.0, .summary = "vertical field of view in degrees"},
        [](auto& f) -> auto& { return f.camera.fov_y_degrees; });
// A patch may place the eye by an orbit around the target instead (proto/README.md §5).
inline constexpr Setting orbit_azimuth =
        range_only("camera/orbit/azimuth", SettingKind::number, -36000.0, 36000.0);
inline constexpr Setting orbit_elevation =
        range_only("camera/orbit/elevation", SettingKind::number, -90.0, 90.0);
inline constexpr Setting orbit_distance =
        range_only("camera/orbit/distance", SettingKind::number, 0.01, 100.0);

inline constexpr Setting light_type = frame_setting(
        "light/type",
        {.summary = "a directional light, or a point light", .command_line = CommandLine::by_hand},
        [](auto& f) -> auto& { return f.light.type; });
inline constexpr Setting light_direction = frame_setting(
        "light/direction",
        {.min = coordinate.min,
         .max = coordinate.max,
         .summary = "toward a directional light; not zero for one",
         .command_line = CommandLine::by_hand},
        [](auto& f) -> auto& { return f.light.direction; });
inline constexpr Setting light_position = frame_setting(
        "light/position",
        {.min = coordinate.min,
         .max = coordinate.max,
         .summary = "a point light's position",
         .command_line = CommandLine::by_hand},
        [](auto& f) -> auto& { return f.light.position; });
inline constexpr Setting light_color = frame_setting(
        "light/color",
        {.min = colour.min, .max = colour.max, .summary = "light colour", .option = "light-color"},
        [](auto& f) -> auto& { return f.light.color; });
inline constexpr Setting light_intensity = frame_setting(
        "light/intensity", {.min = 0.0, .max = 100.0, .summary = "light intensity"},
        [](auto& f) -> auto& { return f.light.intensity; });
inline constexpr Setting light_ambient = frame_setting(
        "light/ambient",
        {.min = 0.0, .max = 1.0, .summary = "ambient light, a fraction of the light colour"},
        [](auto& f) -> auto& { return f.light.ambient; });

inline constexpr Setting mode = frame_setting(
        "settings/mode", {.summary = "rendering mode"},
        [](auto& f) -> auto& { return f.settings.mode; });
inline constexpr Setting compositing = frame_setting(
        "settings/compositing", {.summary = "compositing"},
        [](auto& f) -> auto& { return f.settings.compositing; });
inline constexpr Setting stage = frame_setting(
        "settings/stage", {.summary = "where the ray caster runs"},
        [](auto& f) -> auto& { return f.settings.stage; });
// The image's width and height, each within 1..the device's and the server's largest side.
inline constexpr Setting size{
        .path = "settings/size",
        .kind = SettingKind::size,
        .min = 1.0,
        .max = Limits{}.max_image_side,
        .summary = "image size",
        .limit = &Limits::max_image_side,
        .command_line = CommandLine::option,
        .read =
                [](const State& s) {
                    return SettingValue(s.frame.settings.width, s.frame.settings.height, 0.0);
                },
        .write =
                [](State& s, SettingValue v) {
                    s.frame.settings.width = static_cast<int>(v.x);
                    s.frame.settings.height = static_cast<int>(v.y);
                },
        .read_frame =
                [](const FrameRequest& f) {
                    return SettingValue(f.settings.width, f.settings.height, 0.0);
                },
};

// Finer than 1/16384 of the box resolves nothing more (volumes have at most a few thousand voxels
// a side) and only multiplies the work; at 2 a ray takes one sample inside the box. What a frame
// may cost is bounded separately (FrameWork against the server's max_frame_work).
inline constexpr Setting sample_distance = frame_setting(
        "settings/sample_distance",
        {.min = 1.0 / 16384.0, .max = 2.0, .summary = "ray step, unit = the volume's longest side"},
        [](auto& f) -> auto& { return f.settings.sample_distance; });
inline constexpr Setting opacity_unit_distance = frame_setting(
        "settings/opacity_unit_distance",
        {.min = 1e-4,
         .max = 1.0,
         .summary = "distance the TF opacity refers to",
         .option = "opacity-unit"},
        [](auto& f) -> auto& { return f.settings.opacity_unit_distance; });
inline constexpr Setting early_termination = frame_setting(
        "settings/early_termination",
        {.min = 0.01, .max = 1.0, .summary = "stop a ray once its opacity reaches this"},
        [](auto& f) -> auto& { return f.settings.early_termination; });
inline constexpr Setting background = frame_setting(
        "settings/background",
        {.min = colour.min, .max = colour.max, .summary = "background colour"},
        [](auto& f) -> auto& { return f.settings.background; });
inline constexpr Setting phong = frame_setting(
        "settings/phong", {.summary = "Blinn-Phong on top of shadows (shadow modes)"},
        [](auto& f) -> auto& { return f.settings.phong; });
inline constexpr Setting empty_space_skipping = frame_setting(
        "settings/empty_space_skipping",
        {.summary = "leap over the bricks the transfer function leaves transparent (the same "
                    "image, faster)"},
        [](auto& f) -> auto& { return f.settings.empty_space_skipping; });
inline constexpr Setting jitter = frame_setting(
        "settings/jitter",
        {.summary = "ray-cast modes: per-pixel jittered sample offsets (fine noise instead of "
                    "rings)"},
        [](auto& f) -> auto& { return f.settings.jitter; });
inline constexpr Setting frame_budget_ms = state_setting(
        "settings/frame_budget_ms",
        {.min = 0.0,
         .max = 60000.0,
         .summary = "milliseconds a frame may take: the server picks the method and quality; 0 "
                    "= as set"},
        [](auto& s) -> auto& { return s.frame_budget_ms; });
// Progressive stills: refinement steps after a still frame (0: none).
inline constexpr Setting refinement_steps = state_setting(
        "settings/refinement_steps",
        {.min = 0.0,
         .max = kMaxRefinementSteps,
         .summary = "refinement steps that follow a still frame (jittered ray casts); 0 = none"},
        [](auto& s) -> auto& { return s.refinement_steps; });

inline constexpr Setting diffuse = frame_setting(
        "settings/shading/diffuse",
        {.min = 0.0, .max = 4.0, .summary = "Blinn-Phong diffuse weight"},
        [](auto& f) -> auto& { return f.settings.shading.diffuse; });
inline constexpr Setting specular = frame_setting(
        "settings/shading/specular",
        {.min = 0.0, .max = 4.0, .summary = "Blinn-Phong specular weight"},
        [](auto& f) -> auto& { return f.settings.shading.specular; });
inline constexpr Setting shininess = frame_setting(
        "settings/shading/shininess",
        {.min = 1.0, .max = 1024.0, .summary = "Blinn-Phong exponent"},
        [](auto& f) -> auto& { return f.settings.shading.shininess; });

inline constexpr Setting slices = frame_setting(
        "settings/light_buffer/slices",
        {.min = 1.0,
         .max = Limits{}.max_slices,
         .summary = "light slices, also half-angle's slices",
         .limit = &Limits::max_slices},
        [](auto& f) -> auto& { return f.settings.light_buffer.slices; });
inline constexpr Setting resolution = frame_setting(
        "settings/light_buffer/resolution",
        {.min = 1.0,
         .max = Limits{}.max_light_resolution,
         .summary = "light buffer R x R texels",
         .limit = &Limits::max_light_resolution,
         .option = "light-res"},
        [](auto& f) -> auto& { return f.settings.light_buffer.resolution; });
inline constexpr Setting builder = frame_setting(
        "settings/light_buffer/builder", {.summary = "light-buffer builder"},
        [](auto& f) -> auto& { return f.settings.light_buffer.builder; });
inline constexpr Setting compensation = frame_setting(
        "settings/light_buffer/compensation",
        {.min = 0.0,
         .max = 1000.0,
         .summary = "light-buffer darkening compensation, n in (1+alpha)^n; 0 = off"},
        [](auto& f) -> auto& { return f.settings.light_buffer.compensation; });
inline constexpr Setting slab_samples = frame_setting(
        "settings/light_buffer/slab_samples",
        {.min = 0.0,
         .max = kMaxSlabSamples,
         .summary = "points per light slab: 1 = the slice plane (the paper), 0 = one per voxel"},
        [](auto& f) -> auto& { return f.settings.light_buffer.slab_samples; });
inline constexpr Setting lookup = frame_setting(
        "settings/light_buffer/lookup",
        {.summary = "camera samples read the light buffer: the layer nearer the light + a march "
                    "through the rest of the slab (local), or the paper's interpolation between "
                    "the two nearest layers",
         .option = "light-lookup"},
        [](auto& f) -> auto& { return f.settings.light_buffer.lookup; });

inline constexpr Setting shell_radius = frame_setting(
        "settings/scattering/shell_radius",
        {.min = 1e-4,
         .max = 0.5,
         .summary = "sbrc_shell: distance of the first ring of neighbours, world units"},
        [](auto& f) -> auto& { return f.settings.scattering.shell_radius; });
inline constexpr Setting shell_rings = frame_setting(
        "settings/scattering/shell_rings",
        {.min = 1.0, .max = 4.0, .summary = "sbrc_shell: rings of neighbours"},
        [](auto& f) -> auto& { return f.settings.scattering.shell_rings; });
inline constexpr Setting shell_center_weight = frame_setting(
        "settings/scattering/shell_center_weight",
        {.min = 0.0,
         .max = 1.0,
         .summary = "sbrc_shell: the centre's weight",
         .option = "shell-weight"},
        [](auto& f) -> auto& { return f.settings.scattering.shell_center_weight; });
inline constexpr Setting cone_angle_degrees = frame_setting(
        "settings/scattering/cone_angle",
        {.min = 0.1, .max = 80.0, .summary = "sbrc_cone: angle of the cone of samples, in degrees"},
        [](auto& f) -> auto& { return f.settings.scattering.cone_angle_degrees; });
inline constexpr Setting cone_center_weight = frame_setting(
        "settings/scattering/cone_center_weight",
        {.min = 0.0,
         .max = 1.0,
         .summary = "sbrc_cone: the disc centre's weight",
         .option = "cone-weight"},
        [](auto& f) -> auto& { return f.settings.scattering.cone_center_weight; });

// The JPEG scale (1..100) as libjpeg takes it; encode's kMinJpegQuality..kMaxJpegQuality, which
// session holds it to at compile time.
inline constexpr Setting encoding = state_setting(
        "output/encoding", {.summary = "the format frames are written in"},
        [](auto& s) -> auto& { return s.output.format; });
inline constexpr Setting jpeg_quality = state_setting(
        "output/jpeg_quality", {.min = 1.0, .max = 100.0, .summary = "JPEG quality"},
        [](auto& s) -> auto& { return s.output.jpeg_quality; });

}  // namespace setting

// Every row above, in the order the protocol, the command line's help, hello, the schema and the
// shaders' Settings block list them.
inline constexpr auto kSettings = std::to_array<const Setting*>({
        &setting::coordinate,
        &setting::colour,
        &setting::camera_eye,
        &setting::camera_target,
        &setting::camera_up,
        &setting::fov_degrees,
        &setting::orbit_azimuth,
        &setting::orbit_elevation,
        &setting::orbit_distance,
        &setting::light_type,
        &setting::light_direction,
        &setting::light_position,
        &setting::light_color,
        &setting::light_intensity,
        &setting::light_ambient,
        &setting::mode,
        &setting::compositing,
        &setting::stage,
        &setting::size,
        &setting::sample_distance,
        &setting::opacity_unit_distance,
        &setting::early_termination,
        &setting::background,
        &setting::phong,
        &setting::empty_space_skipping,
        &setting::jitter,
        &setting::frame_budget_ms,
        &setting::refinement_steps,
        &setting::diffuse,
        &setting::specular,
        &setting::shininess,
        &setting::slices,
        &setting::resolution,
        &setting::builder,
        &setting::compensation,
        &setting::slab_samples,
        &setting::lookup,
        &setting::shell_radius,
        &setting::shell_rings,
        &setting::shell_center_weight,
        &setting::cone_angle_degrees,
        &setting::cone_center_weight,
        &setting::encoding,
        &setting::jpeg_quality,
});

// The row whose path is `path`; null for none.
[[nodiscard]] const Setting* setting_at(std::string_view path);

}  // namespace penumbra::scene
