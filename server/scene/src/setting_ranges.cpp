#include "penumbra/scene/setting_ranges.hpp"

#include <cstdio>

namespace penumbra::scene {

std::string SettingRange::describe() const {
    char text[96];
    if (integer) {
        std::snprintf(text, sizeof text, "within %.0f..%.0f", min, max);
    } else {
        std::snprintf(text, sizeof text, "within [%.10g, %.10g]", min, max);
    }
    return text;
}

}  // namespace penumbra::scene
