#pragma once

#include <array>
#include <concepts>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>

namespace penumbra::base {

// One row of an enum's name table: a value and its spelling in the protocol, on the command line
// and in the shaders' defines. Each named enum has one table right after it, a row per value in
// the enum's order, and a `names_of` overload returning it; everything below reads that table.
template <typename Enum>
struct EnumName {
    Enum value;
    std::string_view name;
};

template <typename Enum>
concept NamedEnum = std::is_enum_v<Enum> && requires(Enum value) {
    { names_of(value) } -> std::convertible_to<std::span<const EnumName<Enum>>>;
};

namespace detail {

// The compiler's signature of this function for `Value`: GCC and Clang spell an enumerator by its
// name in it ("Value = penumbra::base::ErrorCode::too_large") and any other value of the enum's
// type as a cast ("Value = (penumbra::base::ErrorCode)200").
template <auto Value>
[[nodiscard]] constexpr std::string_view signature() {
    return __PRETTY_FUNCTION__;
}

}  // namespace detail

// Whether the value `index` of `Enum` is one of its enumerators (see detail::signature).
template <typename Enum, std::size_t index>
[[nodiscard]] constexpr bool is_enumerator() {
    constexpr std::string_view text = detail::signature<static_cast<Enum>(index)>();
    constexpr std::size_t at = text.find("Value = ");
    static_assert(at != std::string_view::npos, "a compiler that spells signatures otherwise");
    return text[at + std::string_view("Value = ").size()] != '(';
}

// Whether `Enum` has no value `count`: after rows for 0..count-1 (our enums count from 0 without
// gaps), no value follows, so a value added after the last row is caught.
template <typename Enum, std::size_t count>
[[nodiscard]] constexpr bool has_values_up_to() {
    return !is_enumerator<Enum, count>();
}

// Whether `table` names every value of the enum in its order, each with a name, and no value
// follows the last row: each table's static_assert, so a value without a row (the last one
// included), or rows out of order, do not compile.
template <typename Enum, std::size_t N>
[[nodiscard]] constexpr bool names_each_value(const std::array<EnumName<Enum>, N>& table) {
    if (!has_values_up_to<Enum, N>()) {
        return false;
    }
    for (std::size_t i = 0; i < N; ++i) {
        if (table[i].value != static_cast<Enum>(i) || table[i].name.empty()) {
            return false;
        }
    }
    return true;
}

template <NamedEnum Enum>
[[nodiscard]] constexpr std::span<const EnumName<Enum>> names() {
    return names_of(Enum{});
}

template <NamedEnum Enum>
[[nodiscard]] constexpr std::string_view name_of(Enum value) {
    return names<Enum>()[static_cast<std::size_t>(value)].name;
}

// The tables' names are string literals, so the view's data is terminated.
template <NamedEnum Enum>
[[nodiscard]] const char* to_string(Enum value) {
    return name_of(value).data();
}

template <NamedEnum Enum>
[[nodiscard]] constexpr std::optional<Enum> parse_name(std::string_view text) {
    for (const EnumName<Enum>& row : names<Enum>()) {
        if (row.name == text) {
            return row.value;
        }
    }
    return std::nullopt;
}

// Every name in the table's order: "per_slice|multi_slice" with separator "|"; with `last`, that
// goes before the last name instead: "alpha or extinction", "a, b or c" for help and error texts.
template <NamedEnum Enum>
[[nodiscard]] std::string name_list(std::string_view separator,
                                    std::optional<std::string_view> last = std::nullopt) {
    const auto table = names<Enum>();
    std::string text;
    for (std::size_t i = 0; i < table.size(); ++i) {
        if (i > 0) {
            text += last && i + 1 == table.size() ? *last : separator;
        }
        text += table[i].name;
    }
    return text;
}

// "alpha or extinction", "none, shell or cone": what an error says a value must be.
template <NamedEnum Enum>
[[nodiscard]] std::string choices() {
    return name_list<Enum>(", ", " or ");
}

}  // namespace penumbra::base
