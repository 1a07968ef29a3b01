#pragma once

// What a client sets: every setting of a frame (FrameRequest) and of a session (State), each
// declared once, its member in a struct below and its row in `setting` at the end, side by side.

#include <penumbra/base/result.hpp>
#include <penumbra/scene/camera.hpp>
#include <penumbra/scene/enum_names.hpp>
#include <penumbra/scene/labels.hpp>
#include <penumbra/scene/light.hpp>
#include <penumbra/scene/mode.hpp>
#include <penumbra/scene/setting.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace penumbra::scene {

// alpha: classic alpha blending with opacity correction a' = 1 - (1 - a)^(dt/dt0).
// extinction: the TF opacity is an extinction coefficient tau = a / dt0, a' = 1 - exp(-tau dt).
enum class Compositing { alpha, extinction };

inline constexpr std::array<EnumName<Compositing>, 2> kCompositingNames{{
        {Compositing::alpha, "alpha"},
        {Compositing::extinction, "extinction"},
}};
static_assert(names_each_value(kCompositingNames));

constexpr std::span<const EnumName<Compositing>> names_of(Compositing) {
    return kCompositingNames;
}

// How the volume is reconstructed between voxels. trilinear: the texture unit's linear filter.
// tricubic: the cubic B-spline (C2, smooths thick slices' terraces) by Sigg & Hadwiger's 8 linear
// fetches per value, its gradient from the B-spline's derivative (3 x 8 fetches): the value
// approximates the voxels rather than passing through them.
enum class Reconstruction { trilinear, tricubic };

inline constexpr std::array<EnumName<Reconstruction>, 2> kReconstructionNames{{
        {Reconstruction::trilinear, "trilinear"},
        {Reconstruction::tricubic, "tricubic"},
}};
static_assert(names_each_value(kReconstructionNames));

constexpr std::span<const EnumName<Reconstruction>> names_of(Reconstruction) {
    return kReconstructionNames;
}

// Where the ray caster runs: a compute shader writing an image, or a fragment shader over a
// full-screen triangle. Both share one source (DESIGN.md §5 asks that both be measurable).
enum class RaycastStage { compute, fragment };

inline constexpr std::array<EnumName<RaycastStage>, 2> kRaycastStageNames{{
        {RaycastStage::compute, "compute"},
        {RaycastStage::fragment, "fragment"},
}};
static_assert(names_each_value(kRaycastStageNames));

constexpr std::span<const EnumName<RaycastStage>> names_of(RaycastStage) {
    return kRaycastStageNames;
}

// How the light attenuation buffer is filled: `per_slice` is the paper's (one pass per slice,
// blending, then a copy into layer k); `multi_slice` is ours (one compute dispatch marching every
// light-space texel through all slices), the paper's "multi-slice per pass" future work.
enum class LightBufferBuilder { per_slice, multi_slice };

inline constexpr std::array<EnumName<LightBufferBuilder>, 2> kLightBufferBuilderNames{{
        {LightBufferBuilder::per_slice, "per_slice"},
        {LightBufferBuilder::multi_slice, "multi_slice"},
}};
static_assert(names_each_value(kLightBufferBuilderNames));

constexpr std::span<const EnumName<LightBufferBuilder>> names_of(LightBufferBuilder) {
    return kLightBufferBuilderNames;
}

// How a camera sample reads the light buffer. `interpolate` is the paper's: linear between the
// two nearest layers, which spreads a surface's own shadow over a whole slab and shows rings of
// the slice spacing on lit surfaces. `local` reads the layer at the slab face nearer the light
// and marches the rest of the way (less than one slab) through the volume, so self-shadowing
// lands where the surface is; it costs up to one slab's samples per lookup.
enum class LightLookup { interpolate, local };

inline constexpr std::array<EnumName<LightLookup>, 2> kLightLookupNames{{
        {LightLookup::interpolate, "interpolate"},
        {LightLookup::local, "local"},
}};
static_assert(names_each_value(kLightLookupNames));

constexpr std::span<const EnumName<LightLookup>> names_of(LightLookup) {
    return kLightLookupNames;
}

// The number of points per light slab is capped: past 16 the slab is sampled finer than any
// volume needs and the build only slows down.
inline constexpr int kMaxSlabSamples = 16;

struct LightBufferSettings {
    int slices = 128;  // n, 1 .. GL_MAX_ARRAY_TEXTURE_LAYERS
    // R: each layer is R x R texels. A light buffer coarser than the image shows in a converged
    // still: at 512x512 its texels' shadow edges leave rings that no refinement step removes
    // (ch2 mri_skin 42.4 dB at R = 256, 48.5 at 512; `penumbra bench stills`); interactive frames
    // halve it (interactive_request).
    int resolution = 512;
    LightBufferBuilder builder = LightBufferBuilder::multi_slice;
    double compensation = 0.0;  // the paper's (1 + alpha)^n darkening compensation; 0 = off
    // Points sampled across each slice's slab along the light: 1 is the paper's single point on
    // the slice plane; 0 picks one per voxel along the light (optics::resolve_slab_samples).
    int slab_samples = 0;                     // 0 .. kMaxSlabSamples
    LightLookup lookup = LightLookup::local;  // the buffer's content does not depend on it

    bool operator==(const LightBufferSettings&) const = default;
};

// Soft shadows from the light buffer. Shell: the light at a sample averaged with its 6 axis
// neighbours at `shell_radius`, 2·radius, ... (`shell_rings` rings), the centre weighted
// `shell_center_weight` and ring i by 1/i. Cone: 8 samples on a disc perpendicular to the light,
// one slice toward it, of radius slice spacing · tan(`cone_angle_degrees`), mixed with the disc
// centre by `cone_center_weight`.
struct ScatteringSettings {
    double shell_radius = 2.0 / 256.0;  // world units
    int shell_rings = 1;                // 1..4
    double shell_center_weight = 0.4;
    double cone_angle_degrees = 30.0;  // (0, 80]
    double cone_center_weight = 0.2;

    bool operator==(const ScatteringSettings&) const = default;
};

struct RenderSettings {
    int width = 512;
    int height = 512;
    Mode mode = Mode::dvr;
    Compositing compositing = Compositing::alpha;
    Reconstruction reconstruction = Reconstruction::trilinear;
    RaycastStage stage = RaycastStage::compute;
    double sample_distance = 1.0 / 256.0;        // world units (the box's longest side is 1)
    double opacity_unit_distance = 1.0 / 256.0;  // dt0: the distance the TF opacity refers to
    double early_termination = 0.99;             // stop a ray once its opacity reaches this
    glm::dvec3 background{0.0};
    Shading shading;
    bool phong = false;  // Blinn-Phong on top of shadows (the shadow modes; `phong` mode always)
    // Rays (camera rays, shadow rays, light-buffer marches) leap over bricks of the volume that
    // the TF leaves fully transparent; the image is the same either way, only the time differs.
    bool empty_space_skipping = true;
    // Ray-cast modes: each pixel's ray takes its samples at a per-pixel offset within the step
    // (a hash pattern) instead of the step's midpoint, so the rings of a fixed step become fine
    // noise that progressive refinement averages away.
    bool jitter = false;
    // Classify each segment between consecutive samples by its front and back values (a table
    // integrated over the TF) instead of each sample: a thin opaque value range between two
    // samples still shows, so steep TFs lose the rings of the sample step.
    bool preintegration = false;
    LightBufferSettings light_buffer;
    ScatteringSettings scattering;

    bool operator==(const RenderSettings&) const = default;
};

// Whether the frame computes gradients: its mode's `gradients`, with the `phong` setting.
bool uses_gradients(const RenderSettings& settings);

// Progressive stills (jittered ray-cast modes). A still frame with `keep` stays on the GPU; the
// refinement steps that follow render the same request with jitter pattern `step` (1, 2, ...) and
// average it with steps 0..step-1, so the image converges toward the integral over each step.
struct Refinement {
    bool keep = false;
    int step = 0;

    bool operator==(const Refinement&) const = default;
};

inline constexpr int kMaxRefinementSteps = 256;
// How many refinement steps may follow a still frame in a new session: the limit, which a still
// whose image stops changing (kDefaultRefinementThreshold) does not reach.
inline constexpr int kDefaultRefinementSteps = 32;
// A still's refinement stops once a step changes its image by no more than this: the RMS of the
// difference over the RGB channels, in 8-bit levels. A step k changes the mean by about the
// frame's noise over k + 1; a quarter of a level is below what an 8-bit image can show twice.
inline constexpr double kDefaultRefinementThreshold = 0.25;

// Whether a still goes on refining after its step `step` (0: the still frame itself), which
// changed the image by `change` (RMS, 8-bit levels; absent for the still frame, which has no
// image before it): not past `max_steps`, and not once a step changed it by `threshold` or less
// (0: only the limit stops it).
bool refines_after(int step, std::optional<double> change, int max_steps, double threshold);

// Refinement steps march at this share of the still's sample distance. A jittered mean converges
// to the image of its own step, whose error no number of steps removes (compositing is not linear
// in the samples), while a finer step removes most of it: `sbrc` at 256x256 against the converged
// truth, ch2 48.5 dB after 13 jittered steps at 1/256 and as much in one unjittered frame at
// 1/512; the CT's bone 41.0 after 32 steps at 1/256, 42.3 in one frame at 1/512.
inline constexpr double kRefinementStepShare = 0.5;

// The request of refinement step `step` (1, 2, ...) of the still `still`: at kRefinementStepShare
// of the still's sample distance (not below the setting's minimum), step 1 starting a mean of its
// own (the still's frame, at the coarser step, is not averaged in) that steps 2, 3, ... average
// into: its Refinement is {keep, step - 1}.
FrameRequest refinement_step_request(const FrameRequest& still, int step);

// A frame that is one tile of a larger image: a picture larger than one frame may be (an export
// of 4096x4096 where a frame holds at most 2048 a side and its work is bounded) is rendered tile by
// tile, each a frame of its own that other sessions' frames may come between. `settings.width`
// and `height` are the tile's; here are the whole image's size and where the tile's top-left pixel
// lies in it. Its pixels are the whole image's exactly: the same rays (pixel_frame) and, jittered,
// the same sample offsets. A zero-sided image: the frame is the whole image.
struct Tile {
    int image_width = 0;
    int image_height = 0;
    int x = 0;
    int y = 0;

    [[nodiscard]] bool whole() const { return image_width == 0 && image_height == 0; }

    bool operator==(const Tile&) const = default;
};

// The largest side of an image rendered in tiles.
inline constexpr int kMaxTiledImageSide = 16384;

// Whether a mode marches camera rays, the only ones jitter and refinement change.
bool is_ray_cast(Mode mode);

// How far from the patient origin a crop face may lie, in millimetres: ten metres, beyond any
// scanner's field of view; a box this large crops nothing.
inline constexpr double kCropReach = 10000.0;

// The box a user cuts the volume down to, in patient coordinates (RAS millimetres, the convention
// of every file Penumbra reads, so that the same numbers cut the same anatomy however a file
// stores its voxels): only what lies inside it is drawn.
struct CropBox {
    bool enabled = false;
    glm::dvec3 min{-kCropReach};
    glm::dvec3 max{kCropReach};

    bool operator==(const CropBox&) const = default;
};

// How many planes a cut may hold, as vtk.js's volume mapper: six, one per face of a box turned any
// way.
inline constexpr int kMaxClipPlanes = 6;

// A plane that cuts the volume, keeping the side its normal points to, in patient coordinates
// (RAS millimetres) as the crop box. The normal need not be unit length, only not zero (validate).
struct ClipPlane {
    bool enabled = false;
    glm::dvec3 point{0.0};
    glm::dvec3 normal{0.0, 0.0, 1.0};

    bool operator==(const ClipPlane&) const = default;
};

// What a user cut away, and whether it still casts shadows: off, a virtual dissection (what is cut
// away neither shows nor shadows what remains); on, the cut only opens a window and the light
// falls as on the whole volume (context shadows). The region drawn is the volume's box cut down by
// it (optics/region.hpp).
struct Cut {
    CropBox crop;
    std::array<ClipPlane, kMaxClipPlanes> planes{};
    bool casts_shadows = false;

    bool operator==(const Cut&) const = default;
};

// Everything one frame depends on besides the volume itself.
struct FrameRequest {
    Camera camera;
    Light light;
    TransferFunction transfer_function;
    RenderSettings settings;
    Cut cut;
    Labels labels;
    Refinement refinement;
    Tile tile;

    bool operator==(const FrameRequest&) const = default;
};

// The frame's pixel rays, `forward + ndc.x * right + ndc.y * up` over the frame's own pixels: the
// camera's frame for the whole image (camera_frame at its aspect), narrowed to the tile's part of
// it.
[[nodiscard]] CameraFrame pixel_frame(const FrameRequest& request);

// Where the frame's pixels lie in the whole image's normalised device coordinates: ndc_image =
// offset + scale * ndc_frame per axis (x right, y up); the identity for a whole frame.
struct ImageWindow {
    glm::dvec2 scale{1.0};
    glm::dvec2 offset{0.0};
};

[[nodiscard]] ImageWindow image_window(const FrameRequest& request);

// The frames that render `whole`'s image in tiles of at most `tile_side` pixels a side, row by row
// from the top left (the last of a row or column may be narrower): `whole` with its size that of
// the tile and its Tile set. Empty when `tile_side` < 1 or `whole` is itself a tile.
[[nodiscard]] std::vector<FrameRequest> image_tiles(const FrameRequest& whole, int tile_side);

// Device limits that bound what a request may ask for.
struct Limits {
    int max_image_side = 8192;
    int max_slices = 2048;             // GL_MAX_ARRAY_TEXTURE_LAYERS
    int max_light_resolution = 16384;  // GL_MAX_TEXTURE_SIZE
};

// Rejects what would make a frame meaningless or unbounded: sizes outside [1, max_image_side],
// non-finite or non-positive distances, a degenerate camera, invalid TF, slices or light-buffer
// sizes beyond the limits, scattering parameters out of range.
base::Status validate(const FrameRequest& request, const Limits& limits = {});

// What a new session's frame starts from: the default camera (the anterior view), a light from
// 10° azimuth and 45° elevation, sbrc with Blinn-Phong, jittered samples (fine noise rather than
// the rings of a fixed step in interactive frames; stills refine it away), and a 512-pixel image,
// 128 light-buffer slices and a 512-texel light buffer as far as `limits` allow; the transfer
// function is left as TransferFunction's default (the session picks its preset).
FrameRequest starting_frame(const Limits& limits);

// The request rendered while a user is interacting: half the image size (at least 64 pixels a
// side), twice the sample distance and half the light buffer's resolution (at least 64 texels),
// a buffer of its own that orbiting reuses and that a light or transfer-function drag rebuilds
// at a quarter of the still's cost. Returns the reduced request and a description of it.
std::pair<FrameRequest, std::string> interactive_request(const FrameRequest& full);

// The frame `request` as it draws its label map alone (Labels::alone), the volume drawn being
// the map's surfaces (volume::label_surfaces' indicator): through
// label_surface_transfer_function, each label in its own colour whole.
FrameRequest labels_alone_request(FrameRequest request);

// How soon the first frame of a still should be on screen when the session sets no frame budget,
// wall milliseconds. A default 512x512 still takes 90-200 ms on llvmpipe (`penumbra bench
// stills`), so it is never previewed there; a portrait tablet's 1536x2048 takes about 2 s.
inline constexpr double kStillPreviewBudgetMs = 250.0;

// A preview holds at most this share of its still's pixels: it delays the still by what it costs,
// so it must cost much less. (A 980x800 still of ch2 on llvmpipe takes 640 ms: with a preview at
// 0.39 of its pixels the first frame came after 420 ms instead of about 800, the still after
// 1060 ms.)
inline constexpr double kStillPreviewMostPixels = 1.0 / 3.0;

// The first frame of a still expected to take `expected_ms`, when that is more than `budget_ms`:
// the same request at a size whose frame takes about the budget (each side scaled by the square
// root of budget over expected time), never below the interactive frame's size, which the viewer
// sees already; the still follows it at full size. Nothing when the still fits its budget, or
// when the preview would hold more than kStillPreviewMostPixels of the still's pixels.
std::optional<FrameRequest> still_preview(const FrameRequest& still, double expected_ms,
                                          double budget_ms);

// The formats a session's frames are written in, by the name the protocol, hello and the frame
// header give them; the first is a new session's. JPEG and PNG frames each stand alone; H.264
// frames are a stream (encode::FrameStream), most of them the change from the frame before.
enum class FrameFormat { jpeg, png, h264 };

inline constexpr std::array<EnumName<FrameFormat>, 3> kFrameFormatNames{{
        {FrameFormat::jpeg, "jpeg"},
        {FrameFormat::png, "png"},
        {FrameFormat::h264, "h264"},
}};
static_assert(names_each_value(kFrameFormatNames));

constexpr std::span<const EnumName<FrameFormat>> names_of(FrameFormat) {
    return kFrameFormatNames;
}

// The JPEG quality frames are written at until a client asks for another.
inline constexpr int kDefaultFrameJpegQuality = 85;

// The rate factor H.264 frames are written at until a client asks for another: at 512x512 about
// the SSIM of JPEG at 85 in a third of the bytes (`penumbra bench encode --stream`).
inline constexpr int kDefaultFrameH264Quality = 22;

// How a session's frames leave the server.
struct Output {
    FrameFormat format = FrameFormat::jpeg;
    int jpeg_quality = kDefaultFrameJpegQuality;
    int h264_quality = kDefaultFrameH264Quality;

    bool operator==(const Output&) const = default;
};

// Everything a session holds that a client can set: what each frame draws, how frames are sent,
// and how the session picks its frames' quality. The one state type: the protocol reads and
// writes it as JSON, the session keeps it, every viewer is sent it.
struct State {
    FrameRequest frame;
    Output output;
    // > 0: the server picks mode, slices, light-buffer resolution and sample distance so that a
    // frame fits this many milliseconds (from the measured accuracy table); 0: as set.
    double frame_budget_ms = 0.0;
    // Progressive stills: at most how many refinement steps follow a still frame of a jittered
    // ray-cast mode (0 turns refinement off), and the change below which they stop sooner.
    int refinement_steps = kDefaultRefinementSteps;
    double refinement_threshold = kDefaultRefinementThreshold;

    bool operator==(const State&) const = default;
};

// Checks every setting of the state against its row (kSettings below) and `limits`, and the
// frame as validate(FrameRequest) does. Errors name the setting's path with dots
// ("light_buffer.slices", "camera.eye", "output.jpeg_quality").
base::Status validate(const State& state, const Limits& limits = {});

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

// Every setting a client can set, each declared once. Adding a setting is its member (in one of the
// structs above) and its row here, listed in kSettings below: one file. From the row:
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
inline constexpr Setting reconstruction = frame_setting(
        "settings/reconstruction",
        {.summary = "volume filter between voxels: trilinear, or the smoother tricubic B-spline "
                    "(about 8 times the fetches)"},
        [](auto& f) -> auto& { return f.settings.reconstruction; });
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
inline constexpr Setting preintegration = frame_setting(
        "settings/preintegration",
        {.summary = "classify the segment between two samples by both values (pre-integrated "
                    "TF): no rings of the step on steep TFs"},
        [](auto& f) -> auto& { return f.settings.preintegration; });
// The crop box's corners in RAS millimetres; each component of min below max's (validate).
inline constexpr Setting crop_enabled = frame_setting(
        "cut/crop/enabled",
        {.summary = "draw only what lies inside the crop box",
         .command_line = CommandLine::by_hand},
        [](auto& f) -> auto& { return f.cut.crop.enabled; });
inline constexpr Setting crop_min = frame_setting(
        "cut/crop/min",
        {.min = -kCropReach,
         .max = kCropReach,
         .summary = "the crop box's corner toward the patient's left, posterior and inferior "
                    "(RAS, mm)",
         .command_line = CommandLine::by_hand},
        [](auto& f) -> auto& { return f.cut.crop.min; });
inline constexpr Setting crop_max = frame_setting(
        "cut/crop/max",
        {.min = -kCropReach,
         .max = kCropReach,
         .summary = "the crop box's corner toward the patient's right, anterior and superior "
                    "(RAS, mm)",
         .command_line = CommandLine::by_hand},
        [](auto& f) -> auto& { return f.cut.crop.max; });

// The clip planes, each a row for its switch, its point and its normal: "cut/plane_1/enabled" ...
// "cut/plane_6/normal".
namespace detail {

inline constexpr std::array<std::array<std::string_view, 3>, kMaxClipPlanes> kClipPlanePaths{{
        {"cut/plane_1/enabled", "cut/plane_1/point", "cut/plane_1/normal"},
        {"cut/plane_2/enabled", "cut/plane_2/point", "cut/plane_2/normal"},
        {"cut/plane_3/enabled", "cut/plane_3/point", "cut/plane_3/normal"},
        {"cut/plane_4/enabled", "cut/plane_4/point", "cut/plane_4/normal"},
        {"cut/plane_5/enabled", "cut/plane_5/point", "cut/plane_5/normal"},
        {"cut/plane_6/enabled", "cut/plane_6/point", "cut/plane_6/normal"},
}};

template <std::size_t Plane>
constexpr std::array<Setting, 3> clip_plane_rows() {
    const auto& paths = kClipPlanePaths[Plane];
    return {frame_setting(
                    paths[0],
                    {.summary = "cut by this plane, keeping the side its normal points to",
                     .command_line = CommandLine::by_hand},
                    [](auto& f) -> auto& { return f.cut.planes[Plane].enabled; }),
            frame_setting(
                    paths[1],
                    {.min = -kCropReach,
                     .max = kCropReach,
                     .summary = "a point of the plane (RAS, mm)",
                     .command_line = CommandLine::by_hand},
                    [](auto& f) -> auto& { return f.cut.planes[Plane].point; }),
            frame_setting(
                    paths[2],
                    {.min = -1.0,
                     .max = 1.0,
                     .summary = "the plane's normal, toward the side kept (RAS); not zero",
                     .command_line = CommandLine::by_hand},
                    [](auto& f) -> auto& { return f.cut.planes[Plane].normal; })};
}

template <std::size_t... Plane>
constexpr auto all_clip_plane_rows(std::index_sequence<Plane...>) {
    std::array<Setting, 3 * sizeof...(Plane)> rows{};
    std::size_t next = 0;
    for (const auto& plane : {clip_plane_rows<Plane>()...}) {
        for (const Setting& row : plane) {
            rows[next++] = row;
        }
    }
    return rows;
}

}  // namespace detail

inline constexpr auto clip_planes =
        detail::all_clip_plane_rows(std::make_index_sequence<kMaxClipPlanes>{});
inline constexpr Setting cut_casts_shadows = frame_setting(
        "cut/casts_shadows",
        {.summary = "what the cut removes still casts shadows (context); off: it neither shows "
                    "nor shadows (virtual dissection)",
         .option = "cut-shadows"},
        [](auto& f) -> auto& { return f.cut.casts_shadows; });
inline constexpr Setting frame_budget_ms = state_setting(
        "settings/frame_budget_ms",
        {.min = 0.0,
         .max = 60000.0,
         .summary = "milliseconds a frame may take: the server picks the method and quality; 0 "
                    "= as set"},
        [](auto& s) -> auto& { return s.frame_budget_ms; });
// Progressive stills: at most this many refinement steps after a still frame (0: none).
inline constexpr Setting refinement_steps = state_setting(
        "settings/refinement_steps",
        {.min = 0.0,
         .max = kMaxRefinementSteps,
         .summary =
                 "at most this many refinement steps follow a still frame (jittered ray casts); 0 "
                 "= none"},
        [](auto& s) -> auto& { return s.refinement_steps; });
inline constexpr Setting refinement_threshold = state_setting(
        "settings/refinement_threshold",
        {.min = 0.0,
         .max = 255.0,
         .summary = "refinement stops once a step changes the still by no more than this (RMS, "
                    "8-bit levels); 0 = only the step limit"},
        [](auto& s) -> auto& { return s.refinement_threshold; });

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
// x264's rate factor (1 .. 51); encode's kMinStreamQuality..kMaxStreamQuality.
inline constexpr Setting h264_quality = state_setting(
        "output/h264_quality",
        {.min = 1.0,
         .max = 51.0,
         .summary = "H.264 frames: x264's rate factor, 1 (nearly lossless) .. 51 (fewer bytes)"},
        [](auto& s) -> auto& { return s.output.h264_quality; });

}  // namespace setting

namespace detail {

// `rows` with the clip planes' rows inserted after the row at `after` (by path: the addresses of
// distinct rows are not comparable in every constant expression).
template <std::size_t Count>
constexpr auto with_clip_planes(const std::array<const Setting*, Count>& rows,
                                std::string_view after) {
    std::array<const Setting*, Count + setting::clip_planes.size()> all{};
    std::size_t next = 0;
    for (const Setting* row : rows) {
        all[next++] = row;
        if (row->path == after) {
            for (const Setting& plane_row : setting::clip_planes) {
                all[next++] = &plane_row;
            }
        }
    }
    return all;
}

}  // namespace detail

// Every row above, in the order the protocol, the command line's help, hello, the schema and the
// shaders' Settings block list them; the clip planes follow the crop box.
inline constexpr auto kSettings = detail::with_clip_planes(std::to_array<const Setting*>({
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
                                                                   &setting::reconstruction,
                                                                   &setting::stage,
                                                                   &setting::size,
                                                                   &setting::sample_distance,
                                                                   &setting::opacity_unit_distance,
                                                                   &setting::early_termination,
                                                                   &setting::background,
                                                                   &setting::phong,
                                                                   &setting::empty_space_skipping,
                                                                   &setting::jitter,
                                                                   &setting::preintegration,
                                                                   &setting::crop_enabled,
                                                                   &setting::crop_min,
                                                                   &setting::crop_max,
                                                                   &setting::cut_casts_shadows,
                                                                   &setting::frame_budget_ms,
                                                                   &setting::refinement_steps,
                                                                   &setting::refinement_threshold,
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
                                                                   &setting::h264_quality,
                                                           }),
                                                           setting::crop_max.path);
static_assert(!kSettings.back()->path.empty(), "the clip planes follow a row of the list");

// The row whose path is `path`; null for none.
[[nodiscard]] const Setting* setting_at(std::string_view path);

}  // namespace penumbra::scene
