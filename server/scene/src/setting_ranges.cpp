#include "penumbra/scene/setting_ranges.hpp"

#include <algorithm>
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

std::string option_name(const SettingRange& range) {
    if (!range.option.empty()) {
        return std::string(range.option);
    }
    std::string name(range.field.substr(range.field.rfind('/') + 1));
    std::replace(name.begin(), name.end(), '_', '-');
    return name;
}

}  // namespace penumbra::scene
