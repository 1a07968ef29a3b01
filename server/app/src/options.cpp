#include "options.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string_view>

namespace penumbra::app {
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

// A finite number, or a fraction "a/b".
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

std::string not_a_number(const std::string& text) {
    return "'" + text + "' is not a finite number";
}

}  // namespace

void validate(boost::any& out, const std::vector<std::string>& texts, Number*, int) {
    const std::string& text = po::validators::get_single_string(texts);
    const auto value = parse_number(text);
    if (!value) {
        throw BadValue(not_a_number(text));
    }
    out = Number{*value};
}

void validate(boost::any& out, const std::vector<std::string>& texts, Numbers*, int) {
    auto numbers = parse_numbers(po::validators::get_single_string(texts), "");
    if (!numbers) {
        throw BadValue(numbers.error().message);
    }
    out = Numbers{*numbers};
}

void validate(boost::any& out, const std::vector<std::string>& texts, Counts*, int) {
    auto numbers = parse_numbers(po::validators::get_single_string(texts), "");
    Counts counts;
    for (const double number : numbers.ok() ? *numbers : std::vector<double>{}) {
        if (number < 1.0 || number > 65536.0 || std::floor(number) != number) {
            throw BadValue("expects whole numbers from 1 to 65536");
        }
        if (std::find(counts.values.begin(), counts.values.end(), int(number)) ==
            counts.values.end()) {
            counts.values.push_back(static_cast<int>(number));
        }
    }
    if (counts.values.empty()) {
        throw BadValue("expects whole numbers from 1 to 65536");
    }
    out = counts;
}

void validate(boost::any& out, const std::vector<std::string>& texts, Modes*, int) {
    Modes modes;
    for (const std::string& name : split_list(po::validators::get_single_string(texts))) {
        const auto mode = scene::parse_mode(name);
        if (!mode) {
            throw BadValue("unknown mode '" + name + "' (" + scene::mode_names() + ")");
        }
        if (std::find(modes.values.begin(), modes.values.end(), *mode) == modes.values.end()) {
            modes.values.push_back(*mode);
        }
    }
    out = modes;
}

void validate(boost::any& out, const std::vector<std::string>& texts, Triple*, int) {
    auto numbers = parse_numbers(po::validators::get_single_string(texts), "");
    if (!numbers || numbers->size() != 3) {
        throw BadValue("expects three comma-separated numbers x,y,z");
    }
    out = Triple{{(*numbers)[0], (*numbers)[1], (*numbers)[2]}};
}

void validate(boost::any& out, const std::vector<std::string>& texts, ImageSize*, int) {
    const std::string& text = po::validators::get_single_string(texts);
    const auto x = text.find('x');
    int w = 0;
    int h = 0;
    const char* end = text.data() + text.size();
    if (x == std::string::npos ||
        std::from_chars(text.data(), text.data() + x, w).ptr != text.data() + x ||
        std::from_chars(text.data() + x + 1, end, h).ptr != end || w <= 0 || h <= 0) {
        throw BadValue("expects WIDTHxHEIGHT, e.g. 512x512");
    }
    out = ImageSize{w, h};
}

std::ostream& operator<<(std::ostream& out, const Number& number) {
    return out << number.value;
}

std::ostream& operator<<(std::ostream& out, const Triple& triple) {
    return out << triple.value.x << ',' << triple.value.y << ',' << triple.value.z;
}

std::ostream& operator<<(std::ostream& out, const ImageSize& size) {
    return out << size.width << 'x' << size.height;
}

std::string shown(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

po::options_description option_group(const std::string& caption) {
    return po::options_description(caption, 100, 60);
}

std::function<void(int)> in_range(int min, int max) {
    return [min, max](int value) {
        if (value < min || value > max) {
            throw BadValue("must be within " + std::to_string(min) + ".." + std::to_string(max));
        }
    };
}

po::typed_value<int>* whole_number(int* target, int min, int max) {
    return po::value<int>(target)->value_name("N")->default_value(*target)->notifier(
            in_range(min, max));
}

base::Result<po::variables_map> parse_options(const std::vector<std::string>& args,
                                              const po::options_description& options) {
    using style = po::command_line_style::style_t;
    const int strict = po::command_line_style::default_style & ~style::allow_guessing;
    po::variables_map values;
    try {
        const po::parsed_options parsed = po::command_line_parser(args)
                                                  .options(options)
                                                  .style(strict)
                                                  .allow_unregistered()
                                                  .run();
        const auto unrecognised = po::collect_unrecognized(parsed.options, po::include_positional);
        if (!unrecognised.empty()) {
            const std::string& first = unrecognised.front();
            return first.starts_with("-")
                           ? base::make_error("invalid_argument", "unknown option",
                                              first.substr(0, first.find('=')))
                           : base::make_error("invalid_argument",
                                              "unexpected argument '" + first + "'", first);
        }
        po::store(parsed, values);
        // po::notify, but with the option named when a range check refuses its value.
        for (const auto& [name, value] : values) {
            try {
                options.find(name, false).semantic()->notify(value.value());
            } catch (const BadValue& error) {
                return base::make_error("invalid_argument", error.message(), "--" + name);
            }
        }
    } catch (const BadValue& error) {
        return base::make_error("invalid_argument", error.message(), error.get_option_name());
    } catch (const po::invalid_command_line_syntax& error) {
        const bool missing = error.kind() == po::invalid_syntax::missing_parameter;
        return base::make_error("invalid_argument", missing ? "needs a value" : error.what(),
                                error.get_option_name());
    } catch (const po::error_with_option_name& error) {
        return base::make_error("invalid_argument", error.what(), error.get_option_name());
    } catch (const po::error& error) {
        return base::make_error("invalid_argument", error.what());
    }
    return values;
}

void print_help(const std::string& usage, const std::string& about,
                const po::options_description& options) {
    std::cout << "usage: penumbra " << usage << "\n\n";
    if (!about.empty()) {
        std::cout << about << "\n\n";
    }
    std::cout << options;
}

int run_subcommand(const std::string& prefix, const char* kind,
                   const std::vector<Subcommand>& subcommands,
                   const std::vector<std::string>& args) {
    const std::string name = args.empty() ? "" : args.front();
    for (const Subcommand& subcommand : subcommands) {
        if (name == subcommand.name) {
            return subcommand.run({args.begin() + 1, args.end()});
        }
    }
    const bool help = name == "--help" || name == "-h" || name == "help";
    if (!help && !name.empty()) {
        std::fprintf(stderr, "%s: unknown %s '%s'\n\n", prefix.c_str(), kind, name.c_str());
    }
    std::printf("usage: %s <%s> [options]\n\n%ss:\n", prefix.c_str(), kind, kind);
    for (const Subcommand& subcommand : subcommands) {
        std::string summary = subcommand.summary;
        for (auto tab = summary.find('\t'); tab != std::string::npos; tab = summary.find('\t')) {
            summary.replace(tab, 1, std::string(11, ' '));
        }
        std::printf("  %-8s %s\n", subcommand.name, summary.c_str());
    }
    std::printf("\n`%s <%s> --help` lists its options.\n", prefix.c_str(), kind);
    return help ? 0 : 2;
}

int report_failure(const char* command, const base::Error& error) {
    std::fprintf(stderr, "penumbra %s: %s\n", command, error.to_string().c_str());
    return 1;
}

int report_usage_error(const char* command, const base::Error& error) {
    std::fprintf(stderr, "penumbra %s: %s (see --help)\n", command, error.to_string().c_str());
    return 2;
}

base::Result<std::vector<double>> parse_numbers(const std::string& text,
                                                const std::string& option) {
    std::vector<double> numbers;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = text.find(',', start);
        const std::string item = text.substr(start, comma - start);
        const auto value = parse_number(item);
        if (!value) {
            return base::make_error("invalid_argument", not_a_number(item), "--" + option);
        }
        numbers.push_back(*value);
        if (comma == std::string::npos) {
            return numbers;
        }
        start = comma + 1;
    }
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

}  // namespace penumbra::app
