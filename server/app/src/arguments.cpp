#include "arguments.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string_view>

namespace penumbra::app {
namespace {

base::Error bad(const std::string& option, const std::string& message) {
    return base::make_error("invalid_argument", message, "--" + option);
}

std::optional<double> parse_plain_double(std::string_view text) {
    double value = 0.0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value);
    if (ec != std::errc() || ptr != end) {
        return std::nullopt;
    }
    return value;
}

// A number, or a fraction "a/b": sample distances are usually quoted as 1/256.
base::Result<double> parse_double(const std::string& text, const std::string& option) {
    const std::size_t slash = text.find('/');
    std::optional<double> value;
    if (slash == std::string::npos) {
        value = parse_plain_double(text);
    } else if (const auto numerator = parse_plain_double(std::string_view(text).substr(0, slash)),
               denominator = parse_plain_double(std::string_view(text).substr(slash + 1));
               numerator && denominator) {
        value = *numerator / *denominator;
    }
    if (!value || !std::isfinite(*value)) {
        return bad(option, "'" + text + "' is not a finite number");
    }
    return *value;
}

}  // namespace

int report_failure(const char* command, const base::Error& error) {
    std::fprintf(stderr, "penumbra %s: %s\n", command, error.to_string().c_str());
    return 1;
}

int report_usage_error(const char* command, const base::Error& error) {
    std::fprintf(stderr, "penumbra %s: %s (see --help)\n", command, error.to_string().c_str());
    return 2;
}

base::Result<Arguments> Arguments::parse(const std::vector<std::string>& args,
                                         const std::vector<std::string>& valued,
                                         const std::vector<std::string>& flags) {
    Arguments out;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& arg = args[i];
        if (arg.rfind("--", 0) != 0) {
            return base::make_error("invalid_argument", "unexpected argument '" + arg + "'", arg);
        }
        std::string name = arg.substr(2);
        std::optional<std::string> inline_value;
        if (const auto eq = name.find('='); eq != std::string::npos) {
            inline_value = name.substr(eq + 1);
            name = name.substr(0, eq);
        }
        const bool takes_value = std::find(valued.begin(), valued.end(), name) != valued.end();
        const bool is_flag = std::find(flags.begin(), flags.end(), name) != flags.end();
        if (!takes_value && !is_flag) {
            return bad(name, "unknown option");
        }
        if (is_flag) {
            if (inline_value) {
                return bad(name, "takes no value");
            }
            out.values_[name] = "";
            continue;
        }
        if (inline_value) {
            out.values_[name] = *inline_value;
        } else if (i + 1 < args.size()) {
            out.values_[name] = args[++i];
        } else {
            return bad(name, "needs a value");
        }
    }
    return out;
}

bool Arguments::has(const std::string& name) const {
    return values_.contains(name);
}

std::optional<std::string> Arguments::get(const std::string& name) const {
    if (auto found = values_.find(name); found != values_.end()) {
        return found->second;
    }
    return std::nullopt;
}

base::Result<double> Arguments::number(const std::string& name, double fallback) const {
    const auto text = get(name);
    return text ? parse_double(*text, name) : base::Result<double>(fallback);
}

base::Result<int> Arguments::integer(const std::string& name, int fallback) const {
    const auto text = get(name);
    if (!text) {
        return fallback;
    }
    int value = 0;
    const char* end = text->data() + text->size();
    const auto [ptr, ec] = std::from_chars(text->data(), end, value);
    if (ec != std::errc() || ptr != end) {
        return bad(name, "'" + *text + "' is not an integer");
    }
    return value;
}

base::Result<std::vector<double>> parse_numbers(const std::string& text,
                                                const std::string& option) {
    std::vector<double> numbers;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = text.find(',', start);
        auto value = parse_double(text.substr(start, comma - start), option);
        if (!value) {
            return value.error();
        }
        numbers.push_back(*value);
        if (comma == std::string::npos) {
            break;
        }
        start = comma + 1;
    }
    return numbers;
}

base::Result<glm::dvec3> Arguments::vec3(const std::string& name, glm::dvec3 fallback) const {
    const auto text = get(name);
    if (!text) {
        return fallback;
    }
    auto numbers = parse_numbers(*text, name);
    if (!numbers) {
        return numbers.error();
    }
    if (numbers->size() != 3) {
        return bad(name, "expects three comma-separated numbers x,y,z");
    }
    return glm::dvec3((*numbers)[0], (*numbers)[1], (*numbers)[2]);
}

base::Result<std::pair<int, int>> Arguments::size(const std::string& name,
                                                  std::pair<int, int> fallback) const {
    const auto text = get(name);
    if (!text) {
        return fallback;
    }
    const auto x = text->find('x');
    int w = 0;
    int h = 0;
    if (x == std::string::npos ||
        std::from_chars(text->data(), text->data() + x, w).ptr != text->data() + x ||
        std::from_chars(text->data() + x + 1, text->data() + text->size(), h).ptr !=
                text->data() + text->size() ||
        w <= 0 || h <= 0) {
        return bad(name, "expects WIDTHxHEIGHT, e.g. 512x512");
    }
    return std::pair{w, h};
}

std::vector<std::string> split_list(const std::string& text, char separator) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t end = std::min(text.find(separator, start), text.size());
        const std::string item = text.substr(start, end - start);
        const auto first = item.find_first_not_of(" \t");
        if (first != std::string::npos) {
            out.push_back(item.substr(first, item.find_last_not_of(" \t") - first + 1));
        }
        start = end + 1;
    }
    return out;
}

base::Result<std::vector<int>> parse_counts(const std::string& text, const std::string& option) {
    auto numbers = parse_numbers(text, option);
    if (!numbers) {
        return numbers.error();
    }
    std::vector<int> counts;
    for (const double number : *numbers) {
        if (number < 1.0 || number > 65536.0 || std::floor(number) != number) {
            return base::make_error("invalid_argument", "expects whole numbers from 1 to 65536",
                                    "--" + option);
        }
        if (std::find(counts.begin(), counts.end(), static_cast<int>(number)) == counts.end()) {
            counts.push_back(static_cast<int>(number));
        }
    }
    return counts;
}

base::Result<std::vector<scene::Mode>> parse_modes(const std::string& text,
                                                   const std::string& option) {
    std::vector<scene::Mode> modes;
    for (const std::string& name : split_list(text)) {
        const auto mode = scene::parse_mode(name);
        if (!mode) {
            return base::make_error("invalid_argument",
                                    "unknown mode '" + name + "' (" + scene::mode_names() + ")",
                                    "--" + option);
        }
        if (std::find(modes.begin(), modes.end(), *mode) == modes.end()) {
            modes.push_back(*mode);
        }
    }
    return modes;
}

}  // namespace penumbra::app
