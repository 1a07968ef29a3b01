#include "penumbra/cli/options.hpp"

#include <penumbra/base/text.hpp>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string_view>

namespace penumbra::cli {

void validate(boost::any& out, const std::vector<std::string>& texts, Number*, int) {
    const std::string& text = po::validators::get_single_string(texts);
    const auto value = base::parse_number(text);
    if (!value) {
        throw BadValue(base::not_a_number(text));
    }
    out = Number{*value};
}

void validate(boost::any& out, const std::vector<std::string>& texts, Numbers*, int) {
    auto numbers = base::parse_numbers(po::validators::get_single_string(texts));
    if (!numbers) {
        throw BadValue(numbers.error().message);
    }
    out = Numbers{*numbers};
}

void validate(boost::any& out, const std::vector<std::string>& texts, Modes*, int) {
    Modes modes;
    for (const std::string& name : base::split_list(po::validators::get_single_string(texts))) {
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
    auto numbers = base::parse_numbers(po::validators::get_single_string(texts));
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

po::typed_value<Number>* at_least(double* target, double min) {
    return po::value<Number>()->value_name("X")->default_value({*target})->notifier(
            [target, min](Number number) {
                if (!(number.value >= min)) {
                    throw BadValue("must be at least " + shown(min));
                }
                *target = number.value;
            });
}

po::typed_value<Number>* number_within(double* target, double min, double max) {
    return po::value<Number>()->value_name("X")->default_value({*target})->notifier(
            [target, min, max](Number number) {
                if (!(number.value >= min && number.value <= max)) {
                    throw BadValue("must be within " + shown(min) + ".." + shown(max));
                }
                *target = number.value;
            });
}

po::typed_value<Number>* seconds(std::chrono::milliseconds* target, double min, double max) {
    const Number fallback{std::chrono::duration<double>(*target).count()};
    return po::value<Number>()->value_name("S")->default_value(fallback)->notifier(
            [target, min, max](Number number) {
                if (!(number.value >= min && number.value <= max)) {
                    throw BadValue("must be within " + shown(min) + ".." + shown(max) + " seconds");
                }
                *target = std::chrono::milliseconds(static_cast<std::int64_t>(number.value * 1e3));
            });
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
                           ? base::make_error(base::ErrorCode::invalid_argument, "unknown option",
                                              first.substr(0, first.find('=')))
                           : base::make_error(base::ErrorCode::invalid_argument,
                                              "unexpected argument '" + first + "'", first);
        }
        po::store(parsed, values);
        // po::notify, but with the option named when a range check refuses its value.
        for (const auto& [name, value] : values) {
            try {
                options.find(name, false).semantic()->notify(value.value());
            } catch (const BadValue& error) {
                return base::make_error(base::ErrorCode::invalid_argument, error.message(),
                                        "--" + name);
            }
        }
    } catch (const BadValue& error) {
        return base::make_error(base::ErrorCode::invalid_argument, error.message(),
                                error.get_option_name());
    } catch (const po::invalid_command_line_syntax& error) {
        const bool missing = error.kind() == po::invalid_syntax::missing_parameter;
        return base::make_error(base::ErrorCode::invalid_argument,
                                missing ? "needs a value" : error.what(), error.get_option_name());
    } catch (const po::error_with_option_name& error) {
        return base::make_error(base::ErrorCode::invalid_argument, error.what(),
                                error.get_option_name());
    } catch (const po::error& error) {
        return base::make_error(base::ErrorCode::invalid_argument, error.what());
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

}  // namespace penumbra::cli
