#pragma once

// How the benchmark plots draw each rendering mode: its colour and gnuplot point type. One row
// per scene::Mode in the enum's order; a mode without a row (one added after the last row
// included), or rows out of order, do not compile.

#include <penumbra/scene/mode.hpp>

#include <array>
#include <cstddef>
#include <string_view>

namespace penumbra::bench {

struct PlotStyle {
    scene::Mode mode;
    std::string_view colour;  // "#rrggbb"
    int point_type;           // gnuplot's `pt`
};

inline constexpr std::array<PlotStyle, 7> kPlotStyles{{
        {scene::Mode::dvr, "#7f7f7f", 5},
        {scene::Mode::phong, "#000000", 7},
        {scene::Mode::half_angle, "#e07b00", 9},
        {scene::Mode::sbrc, "#1f5fbf", 11},
        {scene::Mode::sbrc_shell, "#2a9d3a", 13},
        {scene::Mode::sbrc_cone, "#9b30c0", 15},
        {scene::Mode::reference, "#d62728", 17},
}};

static_assert(scene::has_values_up_to<scene::Mode, kPlotStyles.size()>());
static_assert([] {
    for (std::size_t i = 0; i < kPlotStyles.size(); ++i) {
        if (kPlotStyles[i].mode != static_cast<scene::Mode>(i) || kPlotStyles[i].colour.empty()) {
            return false;
        }
    }
    return true;
}());

[[nodiscard]] constexpr const PlotStyle& plot_style(scene::Mode mode) {
    return kPlotStyles[static_cast<std::size_t>(mode)];
}

}  // namespace penumbra::bench
