#include "penumbra/scene/setting.hpp"

#include <penumbra/scene/frame_request.hpp>

#include <algorithm>
#include <cstdio>

namespace penumbra::scene {

double Setting::max_under(const Limits& limits) const {
    return limit != nullptr ? static_cast<double>(limits.*limit) : max;
}

std::string Setting::describe() const {
    return describe(Limits{});
}

std::string Setting::describe(const Limits& limits) const {
    char text[96];
    if (integer()) {
        std::snprintf(text, sizeof text, "within %.0f..%.0f", min, max_under(limits));
    } else {
        std::snprintf(text, sizeof text, "within [%.10g, %.10g]", min, max_under(limits));
    }
    return text;
}

std::string option_name(const Setting& setting) {
    if (!setting.option.empty()) {
        return std::string(setting.option);
    }
    std::string name(setting.path.substr(setting.path.rfind('/') + 1));
    std::replace(name.begin(), name.end(), '_', '-');
    return name;
}

std::string choice_list(const Setting& setting, std::string_view separator, std::string_view last) {
    std::string text;
    for (std::size_t i = 0; i < setting.choices.size(); ++i) {
        if (i > 0) {
            text += i + 1 == setting.choices.size() ? last : separator;
        }
        text += setting.choices[i];
    }
    return text;
}

const Setting* setting_at(std::string_view path) {
    const auto found = std::find_if(kSettings.begin(), kSettings.end(),
                                    [&](const Setting* setting) { return setting->path == path; });
    return found != kSettings.end() ? *found : nullptr;
}

}  // namespace penumbra::scene
