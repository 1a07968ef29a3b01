#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <boost/program_options.hpp>
#include <glm/vec3.hpp>

#include <chrono>
#include <functional>
#include <iosfwd>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace penumbra::cli {

namespace po = boost::program_options;

// Value types of the command line, read by program_options through `validate` and shown in the
// help (defaults) through `<<`.

// A number, or a fraction "a/b": sample distances are usually quoted as 1/256.
struct Number {
    double value = 0.0;
};

// "x,y,z".
struct Triple {
    glm::dvec3 value{0.0};
};

// "WxH".
struct ImageSize {
    int width = 0;
    int height = 0;
};

// "a,b,c" lists in the order given: numbers (each may be a fraction); modes, each once.
struct Numbers {
    std::vector<double> values;
};

struct Modes {
    std::vector<scene::Mode> values;
};

// A list read by `parse`, the function of the module whose list it is (a Result, its error a
// message).
template <auto parse>
struct ListOf {
    std::decay_t<decltype(*parse(std::string_view{}))> values;
};

void validate(boost::any& out, const std::vector<std::string>& texts, Number*, int);
void validate(boost::any& out, const std::vector<std::string>& texts, Numbers*, int);
void validate(boost::any& out, const std::vector<std::string>& texts, Modes*, int);
void validate(boost::any& out, const std::vector<std::string>& texts, Triple*, int);
void validate(boost::any& out, const std::vector<std::string>& texts, ImageSize*, int);
std::ostream& operator<<(std::ostream& out, const Number& number);
std::ostream& operator<<(std::ostream& out, const Triple& triple);
std::ostream& operator<<(std::ostream& out, const ImageSize& size);

// How the help and the errors write a number (%g).
std::string shown(double value);

// A value refused by a validator or a range check; the error names the option.
class BadValue : public po::error_with_option_name {
public:
    explicit BadValue(const std::string& message)
        : po::error_with_option_name(message)
        , message_(message) {}

    [[nodiscard]] const std::string& message() const { return message_; }

private:
    std::string message_;
};

template <auto parse>
void validate(boost::any& out, const std::vector<std::string>& texts, ListOf<parse>*, int) {
    auto values = parse(po::validators::get_single_string(texts));
    if (!values) {
        throw BadValue(values.error().message);
    }
    out = ListOf<parse>{std::move(*values)};
}

// A group of options laid out for the help (100 columns, descriptions from column 40).
po::options_description option_group(const std::string& caption);

// Refuses a whole number outside min..max (a notifier).
std::function<void(int)> in_range(int min, int max);

// A whole number stored in `target`, whose value is the default, refused outside min..max.
po::typed_value<int>* whole_number(int* target, int min, int max);

// A number stored in `target`, whose value is the default, refused below `min`.
po::typed_value<Number>* at_least(double* target, double min);

// A number stored in `target`, whose value is the default, refused outside min..max.
po::typed_value<Number>* number_within(double* target, double min, double max);

// A time in seconds stored in `target`, whose value is the default, refused outside min..max.
po::typed_value<Number>* seconds(std::chrono::milliseconds* target, double min, double max);

// A memory size given in MiB, refused outside 1..max_mb, stored in bytes in `target`, whose
// value is the default.
template <class Bytes>
po::typed_value<int>* megabytes(Bytes* target, int max_mb) {
    return po::value<int>()
            ->value_name("M")
            ->default_value(static_cast<int>(*target >> 20))
            ->notifier([target, check = in_range(1, max_mb)](int mb) {
                check(mb);
                *target = static_cast<Bytes>(mb) << 20;
            });
}

// Parses `args` against `options` and runs their checks and stores: an unknown option, a stray
// argument, a missing or malformed value is an error naming the option.
base::Result<po::variables_map> parse_options(const std::vector<std::string>& args,
                                              const po::options_description& options);

// `text` read as program_options reads an option's text (a default, valid).
template <class T>
T parsed(const std::string& text) {
    boost::any value;
    validate(value, {text}, static_cast<T*>(nullptr), 0);
    return boost::any_cast<T>(value);
}

// An option whose default is given as text.
template <class T>
po::typed_value<T>* with_default(const char* value_name, const std::string& fallback) {
    return po::value<T>()->value_name(value_name)->default_value(parsed<T>(fallback), fallback);
}

// "usage: penumbra <usage>", what the command does (`about`, may be empty) and its options.
void print_help(const std::string& usage, const std::string& about,
                const po::options_description& options);

// A command (or a benchmark) by name: what it does and how it runs.
struct Subcommand {
    const char* name;
    const char* summary;  // lines after the first start with a tab
    int (*run)(const std::vector<std::string>& args);
};

// Runs the subcommand args[0] names with the arguments after it. Without one, or for an unknown
// one, lists them (exit status 2); for --help likewise, with 0. `kind` is "command" or
// "benchmark", `prefix` "penumbra" or "penumbra bench".
int run_subcommand(const std::string& prefix, const char* kind,
                   const std::vector<Subcommand>& subcommands,
                   const std::vector<std::string>& args);

// Prints "penumbra <command>: <error>" on stderr and returns the exit status of a failed run (1).
int report_failure(const char* command, const base::Error& error);

// The same for a wrong command line (exit status 2), pointing at --help.
int report_usage_error(const char* command, const base::Error& error);

}  // namespace penumbra::cli
