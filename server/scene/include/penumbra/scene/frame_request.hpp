#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/scene/camera.hpp>
#include <penumbra/scene/enum_names.hpp>
#include <penumbra/scene/light.hpp>
#include <penumbra/scene/mode.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <optional>
#include <string>
#include <string_view>

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
    int slices = 128;      // n, 1 .. GL_MAX_ARRAY_TEXTURE_LAYERS
    int resolution = 256;  // R: each layer is R x R texels
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
// How many refinement steps follow a still frame in a new session.
inline constexpr int kDefaultRefinementSteps = 8;

// Whether a mode marches camera rays, the only ones jitter and refinement change.
bool is_ray_cast(Mode mode);

// Everything one frame depends on besides the volume itself.
struct FrameRequest {
    Camera camera;
    Light light;
    TransferFunction transfer_function;
    RenderSettings settings;
    Refinement refinement;

    bool operator==(const FrameRequest&) const = default;
};

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
// 10° azimuth and 45° elevation, sbrc with Blinn-Phong, and a 512-pixel image, 128 light-buffer
// slices and a 256-texel light buffer as far as `limits` allow; the transfer function is left as
// TransferFunction's default (the session picks its preset).
FrameRequest starting_frame(const Limits& limits);

}  // namespace penumbra::scene
