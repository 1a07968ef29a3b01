#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/scene/enum_names.hpp>
#include <penumbra/scene/mode.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>

namespace penumbra::scene {

struct FrameRequest;
struct State;
struct Limits;

// What a setting holds. The kind says how the protocol spells the value (a number, a whole
// number, true/false, one of a list of names, [x, y, z], [width, height]), how the command line
// takes it, how validate checks it, how the JSON Schema and the web client type it and how the
// shaders see it (float, int, int, int, vec3, ivec2).
enum class SettingKind { number, whole, boolean, choice, vector, size };

inline constexpr std::array<EnumName<SettingKind>, 6> kSettingKindNames{{
        {SettingKind::number, "number"},
        {SettingKind::whole, "integer"},
        {SettingKind::boolean, "boolean"},
        {SettingKind::choice, "choice"},
        {SettingKind::vector, "vector"},
        {SettingKind::size, "size"},
}};
static_assert(names_each_value(kSettingKindNames));

constexpr std::span<const EnumName<SettingKind>> names_of(SettingKind) {
    return kSettingKindNames;
}

// A setting's value in one shape for every kind, so that the table can read and write any of
// them: a number, a whole number, a boolean (0 or 1) and a choice (the index of its name) are x;
// a vector is x, y, z; a size is x (width) and y (height).
using SettingValue = glm::dvec3;

// How the command line sets a setting: with an option the table makes (`--sample-distance X`,
// `--phong`, `--no-empty-space-skipping`, `--compositing alpha|extinction`, `--size WxH`,
// `--background R,G,B`), with options of the command line's own (the camera's and the light's
// placement, which it takes as views, orbits and angles), or not at all (what only a session has).
enum class CommandLine { option, by_hand, none };

// The names of an enum's values in the enum's order, for a setting that chooses one. A named enum
// (enum_names.hpp) has them from its name table; the modes from their table.
template <class Enum>
inline constexpr auto kChoiceNames = [] {
    constexpr auto table = names_of(Enum{});
    std::array<std::string_view, table.size()> names{};
    for (std::size_t i = 0; i < table.size(); ++i) {
        names[i] = table[i].name;
    }
    return names;
}();

template <>
inline constexpr auto kChoiceNames<Mode> = [] {
    std::array<std::string_view, kModes.size()> names{};
    for (std::size_t i = 0; i < kModes.size(); ++i) {
        names[i] = kModes[i].name;
    }
    return names;
}();

// What each choice does, where the enum says: the modes' summaries.
template <class Enum>
inline constexpr std::array<std::string_view, 0> kChoiceSummaries{};

template <>
inline constexpr auto kChoiceSummaries<Mode> = [] {
    std::array<std::string_view, kModes.size()> summaries{};
    for (std::size_t i = 0; i < kModes.size(); ++i) {
        summaries[i] = kModes[i].summary;
    }
    return summaries;
}();

// What a row says besides its path and its member, by name: `{.min = 0.0, .max = 1.0, .summary =
// "ambient light"}`.
struct SettingSpec {
    // Each component's range, both ends included (a number, a whole number, a vector, a size).
    double min = 0.0;
    double max = 0.0;
    // What the setting does, for the command line's help, hello (a client's hint) and the schema.
    std::string_view summary = {};
    // A whole number or size bounded by the device and the server's configuration (scene::Limits)
    // instead of `max`, which is then that limit's default.
    int Limits::*limit = nullptr;
    // The command-line option, where it is not the path's last part with '-' for '_'.
    std::string_view option = {};
    CommandLine command_line = CommandLine::option;
};

// One setting: where the protocol puts it (its path in the state and in proto/v1's schemas,
// "settings/light_buffer/compensation"), what it holds and how to read and write it in a state.
// Each setting is declared once, as a row of frame_request.hpp, next to its member; the protocol's
// parser and printer, validate, the command line, hello, the JSON Schema, the shaders' Settings
// block and the web client's types and defaults all walk the rows.
struct Setting {
    std::string_view path;
    SettingKind kind = SettingKind::number;
    double min = 0.0;
    double max = 0.0;
    std::string_view summary = {};
    // A choice's names, in the enum's order, and what each does where the enum says.
    std::span<const std::string_view> choices = {};
    std::span<const std::string_view> choice_summaries = {};
    int Limits::*limit = nullptr;
    std::string_view option = {};
    CommandLine command_line = CommandLine::none;
    // The value in a state, and storing one (checked first: within the range, a known choice).
    // Null for a range that no state member holds (an orbit's angles, which a patch turns into
    // the camera's eye; the components of coordinates and colours).
    SettingValue (*read)(const State&) = nullptr;
    void (*write)(State&, SettingValue) = nullptr;
    // The value in a frame, for a setting that every frame carries (the shaders see those); null
    // for a setting of the session (its output, its frame budget).
    SettingValue (*read_frame)(const FrameRequest&) = nullptr;

    [[nodiscard]] constexpr bool held() const { return read != nullptr; }

    [[nodiscard]] constexpr bool in_frame() const { return read_frame != nullptr; }

    // A whole number in every component (whole numbers, sizes).
    [[nodiscard]] constexpr bool integer() const {
        return kind == SettingKind::whole || kind == SettingKind::size;
    }

    // The largest value a component may take under `limits`.
    [[nodiscard]] double max_under(const Limits& limits) const;

    // NaN and infinities are never within.
    [[nodiscard]] constexpr bool contains(double value) const {
        return value >= min && value <= max;
    }

    // "within [0.0001, 0.5]" or "within 1..4", for error messages; with `limits` for a setting
    // bounded by them.
    [[nodiscard]] std::string describe() const;
    [[nodiscard]] std::string describe(const Limits& limits) const;
};

// The command-line option that sets `setting`: "compensation" for
// "settings/light_buffer/compensation", "sample-distance" for "settings/sample_distance".
std::string option_name(const Setting& setting);

// Whether `value` is one `setting` may take under `limits`: each component within its range (NaN
// never is). The error names the setting's path with dots ("light_buffer.slices",
// "camera.eye"), as validate does.
base::Status validate_value(const Setting& setting, SettingValue value, const Limits& limits);

// A choice's names: "per_slice|multi_slice" with separator "|"; with `last`, that goes before the
// last name instead ("alpha or extinction"), for help and error texts.
std::string choice_list(const Setting& setting, std::string_view separator, std::string_view last);

// A range that no state member holds: for the parts of a patch that are instructions rather than
// values (an orbit), and the components that vector settings share.
constexpr Setting range_only(std::string_view path, SettingKind kind, double min, double max) {
    return Setting{.path = path, .kind = kind, .min = min, .max = max};
}

namespace detail {

template <class Value>
constexpr SettingKind kind_of() {
    if constexpr (std::is_same_v<Value, bool>) {
        return SettingKind::boolean;
    } else if constexpr (std::is_enum_v<Value>) {
        return SettingKind::choice;
    } else if constexpr (std::is_integral_v<Value>) {
        return SettingKind::whole;
    } else if constexpr (std::is_floating_point_v<Value>) {
        return SettingKind::number;
    } else {
        static_assert(std::is_same_v<Value, glm::dvec3>,
                      "a setting is a number, a boolean, an enum or a glm::dvec3");
        return SettingKind::vector;
    }
}

template <class Value>
SettingValue to_value(const Value& value) {
    if constexpr (std::is_same_v<Value, glm::dvec3>) {
        return value;
    } else {
        return SettingValue(static_cast<double>(value), 0.0, 0.0);
    }
}

template <class Value>
Value from_value(SettingValue value) {
    if constexpr (std::is_same_v<Value, glm::dvec3>) {
        return value;
    } else if constexpr (std::is_same_v<Value, bool>) {
        return value.x != 0.0;
    } else if constexpr (std::is_enum_v<Value>) {
        return static_cast<Value>(static_cast<int>(value.x));
    } else {
        return static_cast<Value>(value.x);
    }
}

template <class Value>
constexpr Setting row(std::string_view path, const SettingSpec& spec) {
    Setting setting{.path = path,
                    .kind = kind_of<Value>(),
                    .min = spec.min,
                    .max = spec.max,
                    .summary = spec.summary,
                    .limit = spec.limit,
                    .option = spec.option,
                    .command_line = spec.command_line};
    if constexpr (std::is_enum_v<Value>) {
        setting.choices = kChoiceNames<Value>;
        setting.choice_summaries = kChoiceSummaries<Value>;
        setting.max = static_cast<double>(kChoiceNames<Value>.size() - 1);
    } else if constexpr (std::is_same_v<Value, bool>) {
        setting.max = 1.0;
    }
    return setting;
}

}  // namespace detail

}  // namespace penumbra::scene
