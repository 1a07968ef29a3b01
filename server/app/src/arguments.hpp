#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <glm/vec3.hpp>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::app {

// `--name value` and `--flag` options of one subcommand. Every option must be declared, so a
// misspelt option is an error rather than silently ignored.
class Arguments {
public:
    // `valued` options take a value, `flags` do not.
    static base::Result<Arguments> parse(const std::vector<std::string>& args,
                                         const std::vector<std::string>& valued,
                                         const std::vector<std::string>& flags);

    [[nodiscard]] bool has(const std::string& name) const;
    [[nodiscard]] std::optional<std::string> get(const std::string& name) const;

    base::Result<double> number(const std::string& name, double fallback) const;
    base::Result<int> integer(const std::string& name, int fallback) const;

    // "x,y,z" → vector.
    base::Result<glm::dvec3> vec3(const std::string& name, glm::dvec3 fallback) const;

    // "WxH" → width, height.
    base::Result<std::pair<int, int>> size(const std::string& name,
                                           std::pair<int, int> fallback) const;

private:
    std::map<std::string, std::string> values_;
};

// Prints "penumbra <command>: <error>" on stderr and returns the exit status of a failed run (1).
int report_failure(const char* command, const base::Error& error);

// The same for a wrong command line (exit status 2), pointing at --help.
int report_usage_error(const char* command, const base::Error& error);

// Splits "a,b,c" into numbers; errors name the option.
base::Result<std::vector<double>> parse_numbers(const std::string& text, const std::string& option);

// "a, b,c" -> {"a", "b", "c"}: items trimmed of blanks, empty ones dropped.
std::vector<std::string> split_list(const std::string& text, char separator = ',');

// "64,128,256" -> whole numbers from 1 to 65536, each once, in the order given.
base::Result<std::vector<int>> parse_counts(const std::string& text, const std::string& option);

// "dvr,sbrc" -> modes, each once, in the order given.
base::Result<std::vector<scene::Mode>> parse_modes(const std::string& text,
                                                   const std::string& option);

}  // namespace penumbra::app
