#include <penumbra/base/text.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>

namespace penumbra::base {
namespace {

std::optional<double> parse_plain_double(std::string_view text) {
    double value = 0.0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value);
    if (ec != std::errc() || ptr != end) {
        return std::nullopt;
    }
    return value;
}

}  // namespace

std::vector<std::string> split_list(std::string_view text, char separator) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t end = std::min(text.find(separator, start), text.size());
        const std::string_view item = text.substr(start, end - start);
        const auto first = item.find_first_not_of(" \t");
        if (first != std::string_view::npos) {
            out.emplace_back(item.substr(first, item.find_last_not_of(" \t") - first + 1));
        }
        start = end + 1;
    }
    return out;
}

std::optional<double> parse_number(std::string_view text) {
    const std::size_t slash = text.find('/');
    std::optional<double> value;
    if (slash == std::string_view::npos) {
        value = parse_plain_double(text);
    } else if (const auto numerator = parse_plain_double(text.substr(0, slash)),
               denominator = parse_plain_double(text.substr(slash + 1));
               numerator && denominator) {
        value = *numerator / *denominator;
    }
    return value && std::isfinite(*value) ? value : std::nullopt;
}

std::string not_a_number(std::string_view text) {
    return "'" + std::string(text) + "' is not a finite number";
}

Result<std::vector<double>> parse_numbers(std::string_view text, std::string where) {
    std::vector<double> numbers;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = text.find(',', start);
        const std::string_view item = text.substr(start, comma - start);
        const auto value = parse_number(item);
        if (!value) {
            return make_error(base::ErrorCode::invalid_argument, not_a_number(item),
                              std::move(where));
        }
        numbers.push_back(*value);
        if (comma == std::string_view::npos) {
            return numbers;
        }
        start = comma + 1;
    }
}

namespace {

// The length of the valid UTF-8 sequence at the start of `text` (RFC 3629: no overlong forms, no
// surrogates, nothing beyond U+10FFFF), or 0 when it starts with none.
std::size_t utf8_sequence(std::string_view text) {
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
    const unsigned char lead = byte(0);
    if (lead < 0x80) {
        return 1;
    }
    std::size_t length = 0;
    unsigned char low = 0x80;
    unsigned char high = 0xBF;
    if (lead >= 0xC2 && lead <= 0xDF) {
        length = 2;
    } else if (lead >= 0xE0 && lead <= 0xEF) {
        length = 3;
        low = lead == 0xE0 ? 0xA0 : 0x80;
        high = lead == 0xED ? 0x9F : 0xBF;
    } else if (lead >= 0xF0 && lead <= 0xF4) {
        length = 4;
        low = lead == 0xF0 ? 0x90 : 0x80;
        high = lead == 0xF4 ? 0x8F : 0xBF;
    } else {
        return 0;
    }
    if (text.size() < length || byte(1) < low || byte(1) > high) {
        return 0;
    }
    for (std::size_t i = 2; i < length; ++i) {
        if (byte(i) < 0x80 || byte(i) > 0xBF) {
            return 0;
        }
    }
    return length;
}

}  // namespace

std::string valid_utf8(std::string_view text, std::size_t max_bytes) {
    std::string out;
    while (!text.empty()) {
        const std::size_t length = std::max<std::size_t>(1, utf8_sequence(text));
        const bool valid = utf8_sequence(text) != 0;
        if (out.size() + (valid ? length : 1) > max_bytes) {
            break;
        }
        out += valid ? text.substr(0, length) : std::string_view("?");
        text.remove_prefix(length);
    }
    return out;
}

}  // namespace penumbra::base
