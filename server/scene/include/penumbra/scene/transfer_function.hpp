#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/scene/enum_names.hpp>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <array>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::scene {

// Piecewise-linear colour and opacity over the volume's values. Positions are normalised (0 is the
// volume's minimum, 1 its maximum, so a preset suits any volume of its kind) or, for the CT
// presets, Hounsfield units, which mean the same tissue on every CT whatever its range.
struct ColorPoint {
    double x = 0.0;
    glm::dvec3 rgb{0.0};

    bool operator==(const ColorPoint&) const = default;
};

struct OpacityPoint {
    double x = 0.0;
    double alpha = 0.0;

    bool operator==(const OpacityPoint&) const = default;
};

enum class PositionSpace { normalized, hounsfield };

inline constexpr std::array<EnumName<PositionSpace>, 2> kPositionSpaceNames{{
        {PositionSpace::normalized, "normalized"},
        {PositionSpace::hounsfield, "hounsfield"},
}};
static_assert(names_each_value(kPositionSpaceNames));

constexpr std::span<const EnumName<PositionSpace>> names_of(PositionSpace) {
    return kPositionSpaceNames;
}

struct TransferFunction {
    std::string name;
    std::vector<ColorPoint> colors;       // sorted by x
    std::vector<OpacityPoint> opacities;  // sorted by x
    PositionSpace space = PositionSpace::normalized;

    // Colour and opacity at value x (in `space`): linear between points, constant beyond the
    // ends. No points at all means black / fully transparent.
    [[nodiscard]] glm::dvec4 evaluate(double x) const;

    bool operator==(const TransferFunction&) const = default;
};

// Checks positions (finite, non-decreasing, in [0,1] when normalised, within
// +-max_hounsfield_position in HU), colours and opacities (finite, in [0,1]).
base::Status validate(const TransferFunction& tf);

inline constexpr double max_hounsfield_position = 100000.0;

// What a table is baked for: the volume's value range, and whether its values are Hounsfield
// units.
struct ValueDomain {
    double min = 0.0;
    double max = 1.0;
    bool hounsfield = false;
};

// The range Hounsfield positions are read over on a volume whose values are not marked as HU (a
// CT stored as a raw file): the 12-bit range of CT scanners.
inline constexpr ValueDomain nominal_ct_domain{-1024.0, 3071.0, true};

// The table the renderers sample: `size` RGBA entries over the volume's range, entry i for the
// value at fraction i / (size - 1) of it (normalised positions: evaluate(i / (size - 1)), the
// same on every volume; Hounsfield positions: evaluated at that value in HU, over the volume's
// range when its values are HU, else over nominal_ct_domain). Both the GPU (as a linearly
// filtered 1D texture) and the CPU reference read this same table.
std::vector<glm::vec4> bake(const TransferFunction& tf, int size, const ValueDomain& values = {});

inline constexpr int default_table_size = 1024;

// Named presets: "grey_ramp", "mri_skin", "mri_brain" (normalised), and the CT presets
// "ct_bone", "ct_skin", "ct_soft_tissue", "ct_lung", "ct_angio" (in Hounsfield units).
base::Result<TransferFunction> preset(std::string_view name);

std::vector<std::string> preset_names();

// The presets in Hounsfield units, the ones that suit a volume whose values are HU.
std::vector<std::string> hounsfield_preset_names();

}  // namespace penumbra::scene
