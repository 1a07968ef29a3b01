#pragma once

#include <penumbra/scene/enum_names.hpp>

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace penumbra::scene {

// The rendering methods of DESIGN.md §1. Each has one row in `kModes` below, in this order, which
// the planner, the work estimate, hello, help texts, benches and tests read.
enum class Mode { dvr, phong, half_angle, sbrc, sbrc_shell, sbrc_cone, reference };

// How a mode draws: a ray caster from the camera, or half-angle slicing (Kniss et al.: an eye
// pass and a light pass per slice).
enum class Technique { ray_casting, half_angle_slicing };

inline constexpr std::array<EnumName<Technique>, 2> kTechniqueNames{{
        {Technique::ray_casting, "ray_casting"},
        {Technique::half_angle_slicing, "half_angle_slicing"},
}};
static_assert(names_each_value(kTechniqueNames));

constexpr std::span<const EnumName<Technique>> names_of(Technique) {
    return kTechniqueNames;
}

// Where a ray-cast sample's light comes from. The values are the shaders' SHADOWS_* defines.
enum class ShadowKind { none = 0, light_buffer = 1, rays = 2 };

inline constexpr std::array<EnumName<ShadowKind>, 3> kShadowKindNames{{
        {ShadowKind::none, "none"},
        {ShadowKind::light_buffer, "light_buffer"},
        {ShadowKind::rays, "rays"},
}};
static_assert(names_each_value(kShadowKindNames));

constexpr std::span<const EnumName<ShadowKind>> names_of(ShadowKind) {
    return kShadowKindNames;
}

// Soft shadows gathered around a sample in the light buffer. The values are the shaders'
// SCATTERING_* defines.
enum class ScatteringKind { none = 0, shell = 1, cone = 2 };

inline constexpr std::array<EnumName<ScatteringKind>, 3> kScatteringKindNames{{
        {ScatteringKind::none, "none"},
        {ScatteringKind::shell, "shell"},
        {ScatteringKind::cone, "cone"},
}};
static_assert(names_each_value(kScatteringKindNames));

constexpr std::span<const EnumName<ScatteringKind>> names_of(ScatteringKind) {
    return kScatteringKindNames;
}

// When a mode computes gradients (central differences) for Blinn-Phong shading.
enum class Gradients {
    never,       // plain emission-absorption; the `phong` setting is ignored
    with_phong,  // when the `phong` setting asks for shading on top of the shadows
    always,
};

inline constexpr std::array<EnumName<Gradients>, 3> kGradientsNames{{
        {Gradients::never, "never"},
        {Gradients::with_phong, "with_phong"},
        {Gradients::always, "always"},
}};
static_assert(names_each_value(kGradientsNames));

constexpr std::span<const EnumName<Gradients>> names_of(Gradients) {
    return kGradientsNames;
}

// Inner-loop iterations one ray-cast sample costs, for the frame's work estimate and the ray
// caster's loop budget (iterations_per_sample): `fixed` + `per_shell_ring` x the shell rings,
// plus the local lookup's slab march for light-buffer shadows and a whole ray for shadow rays.
struct SampleCost {
    int fixed = 1;
    int per_shell_ring = 0;
};

// What one mode is: its names, how it draws and what a sample costs.
struct ModeInfo {
    Mode mode;
    std::string_view name;     // the protocol's and the command line's spelling
    std::string_view summary;  // one line for help texts and the client's method panel
    Technique technique;
    ShadowKind shadows;
    ScatteringKind scattering;
    Gradients gradients;
    SampleCost cost;
    bool is_reference;  // the ground truth the accuracy benchmark measures against
};

// clang-format off
inline constexpr std::array<ModeInfo, 7> kModes{{
    // mode, name, summary,
    //     technique, shadows, scattering, gradients, cost {fixed, per shell ring},
    //     is_reference
    {Mode::dvr, "dvr", "ray casting, emission-absorption, no shading",
        Technique::ray_casting, ShadowKind::none, ScatteringKind::none, Gradients::never, {1, 0},
        false},
    {Mode::phong, "phong", "ray casting with gradients and Blinn-Phong shading",
        Technique::ray_casting, ShadowKind::none, ScatteringKind::none, Gradients::always, {1, 0},
        false},
    {Mode::half_angle, "half_angle", "half-angle slicing (Kniss et al. 2002)",
        Technique::half_angle_slicing, ShadowKind::none, ScatteringKind::none,
        Gradients::with_phong, {1, 0},
        false},
    {Mode::sbrc, "sbrc", "slice-based ray casting: shadows from the light buffer",
        Technique::ray_casting, ShadowKind::light_buffer, ScatteringKind::none,
        Gradients::with_phong, {1, 0},
        false},
    {Mode::sbrc_shell, "sbrc_shell", "sbrc + light averaged over shells of neighbours",
        Technique::ray_casting, ShadowKind::light_buffer, ScatteringKind::shell,
        Gradients::with_phong, {4, 2},
        false},
    {Mode::sbrc_cone, "sbrc_cone", "sbrc + light gathered on a cone toward the light",
        Technique::ray_casting, ShadowKind::light_buffer, ScatteringKind::cone,
        Gradients::with_phong, {10, 0},
        false},
    {Mode::reference, "reference", "a shadow ray from every sample: the ground truth",
        Technique::ray_casting, ShadowKind::rays, ScatteringKind::none, Gradients::with_phong,
        {2, 0},
        true},
}};
// clang-format on

// A mode without a row (one added after `reference` included), or rows out of order, does not
// compile.
static_assert(has_values_up_to<Mode, kModes.size()>());
static_assert([] {
    for (std::size_t i = 0; i < kModes.size(); ++i) {
        if (kModes[i].mode != static_cast<Mode>(i)) {
            return false;
        }
    }
    return true;
}());

[[nodiscard]] constexpr const ModeInfo& describe(Mode mode) {
    return kModes[static_cast<std::size_t>(mode)];
}

[[nodiscard]] constexpr std::span<const ModeInfo> modes() {
    return kModes;
}

const char* to_string(Mode mode);
std::optional<Mode> parse_mode(std::string_view text);

// "dvr, phong, ..., reference": every mode's name, for help and error texts.
[[nodiscard]] std::string mode_names(std::string_view separator = ", ");

// Whether the mode reads the light attenuation buffer (and so builds one).
[[nodiscard]] constexpr bool uses_light_buffer(Mode mode) {
    return describe(mode).shadows == ShadowKind::light_buffer;
}

// Whether the mode works in the light's view (a light buffer, or slicing toward the light).
[[nodiscard]] constexpr bool uses_light_view(Mode mode) {
    return uses_light_buffer(mode) || describe(mode).technique == Technique::half_angle_slicing;
}

}  // namespace penumbra::scene
