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

}  // namespace penumbra::base
