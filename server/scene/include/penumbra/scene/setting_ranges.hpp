#pragma once

#include <array>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

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
    // Stores a value within the range in the request (whole where `integer`): the protocol
    // parser and the command line set the setting through it. Null exactly where `read` is.
    void (*write)(FrameRequest&, double) = nullptr;
    // What the setting does, for the command line's help and hello's ranges (a client's hint);
    // empty where `write` is null.
    std::string_view summary = {};
    // The command-line option that sets it, where that is not the field's last part with '-'
    // for '_' (see option_name).
    std::string_view option = {};

    // NaN and infinities are never within.
    [[nodiscard]] constexpr bool contains(double value) const {
        return value >= min && value <= max;
    }

    // "within [0.0001, 0.5]" or "within 1..4", for error messages.
    [[nodiscard]] std::string describe() const;
};

// The command-line option that sets `range`: "compensation" for
// "settings/light_buffer/compensation", "sample-distance" for "settings/sample_distance".
std::string option_name(const SettingRange& range);

// The range of a setting that one member of a request holds, which `member` picks out of it:
// request_setting("light/ambient", 0.0, 1.0, "ambient light",
//                 [](auto& r) -> auto& { return r.light.ambient; }).
// The row reads and writes that member, and is whole when the member is.
template <class Member>
constexpr SettingRange request_setting(std::string_view field, double min, double max,
                                       std::string_view summary, Member,
                                       std::string_view option = {}) {
    using Value = std::remove_cvref_t<decltype(Member{}(std::declval<FrameRequest&>()))>;
    static_assert(std::is_arithmetic_v<Value> && !std::is_same_v<Value, bool>,
                  "a setting with a range is a number");
    return SettingRange{
            field,
            min,
            max,
            std::is_integral_v<Value>,
            [](const FrameRequest& r) { return static_cast<double>(Member{}(r)); },
            [](FrameRequest& r, double value) { Member{}(r) = static_cast<Value>(value); },
            summary,
            option};
}

// The number of points per light slab is capped: past 16 the slab is sampled finer than any
// volume needs and the build only slows down.
inline constexpr int kMaxSlabSamples = 16;

}  // namespace penumbra::scene
