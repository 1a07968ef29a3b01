#pragma once

#include <penumbra/base/result.hpp>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace penumbra::scene {

// Piecewise-linear colour and opacity over the volume's value range. Positions are normalised:
// 0 is the volume's minimum, 1 its maximum, so a preset suits any volume of its kind.
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

struct TransferFunction {
    std::string name;
    std::vector<ColorPoint> colors;     // sorted by x
    std::vector<OpacityPoint> opacities;  // sorted by x

    // Colour and opacity at normalised value x: linear between points, constant beyond the ends.
    // No points at all means black / fully transparent.
    [[nodiscard]] glm::dvec4 evaluate(double x) const;

    bool operator==(const TransferFunction&) const = default;
};

// Checks positions (finite, in [0,1], non-decreasing), colours and opacities (finite, in [0,1]).
base::Status validate(const TransferFunction& tf);

// The table the renderers sample: `size` RGBA entries, entry i holding evaluate(i / (size - 1)).
// Both the GPU (as a linearly filtered 1D texture) and the CPU reference read this same table.
std::vector<glm::vec4> bake(const TransferFunction& tf, int size);

inline constexpr int default_table_size = 1024;

// Named presets: "grey_ramp", "mri_skin", "mri_brain", "ct_skin", "ct_bone".
base::Result<TransferFunction> preset(std::string_view name);

std::vector<std::string> preset_names();

}  // namespace penumbra::scene
