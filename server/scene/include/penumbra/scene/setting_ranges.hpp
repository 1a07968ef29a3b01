#pragma once

#include <array>
#include <string>
#include <string_view>

namespace penumbra::scene {

struct FrameRequest;

// The values one setting may take, both ends included, under its protocol name (the path in
// proto/v1/common.schema.json's $defs: "settings/light_buffer/compensation"). Each setting's
// range is declared once, next to the settings (scene::setting in frame_request.hpp):
// scene::validate, the protocol parser and the command line read it, and a test holds the JSON
// Schemas' minimum and maximum against kSettingRanges.
struct SettingRange {
    std::string_view field;
    double min;
    double max;
    bool integer = false;
    // The setting's value in a request, which validate checks; null where validate checks the
    // setting another way (vectors) or a request does not hold it (the orbit of a camera patch).
    double (*read)(const FrameRequest&) = nullptr;

    // NaN and infinities are never within.
    [[nodiscard]] constexpr bool contains(double value) const {
        return value >= min && value <= max;
    }

    // "within [0.0001, 0.5]" or "within 1..4", for error messages.
    [[nodiscard]] std::string describe() const;
};

// The number of points per light slab is capped: past 16 the slab is sampled finer than any
// volume needs and the build only slows down.
inline constexpr int kMaxSlabSamples = 16;

}  // namespace penumbra::scene
