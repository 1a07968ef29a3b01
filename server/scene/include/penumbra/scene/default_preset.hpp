#pragma once

#include <string_view>

namespace penumbra::scene {

// The transfer-function presets a volume is shown with when nobody names one (`render`, `bench`
// and new `serve` sessions): a CT, whose values are Hounsfield units, shows its bone; anything
// else the MRI heads' skin, whose positions are fractions of the volume's range.
inline constexpr std::string_view kDefaultPreset = "mri_skin";
inline constexpr std::string_view kDefaultHounsfieldPreset = "ct_bone";

[[nodiscard]] constexpr std::string_view default_preset(bool values_in_hounsfield_units) {
    return values_in_hounsfield_units ? kDefaultHounsfieldPreset : kDefaultPreset;
}

}  // namespace penumbra::scene
