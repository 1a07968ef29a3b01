#pragma once

// Lists and numbers as people type them on a command line or in a config value.

#include <penumbra/base/result.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::base {

// "a, b,c" -> {"a", "b", "c"}: items trimmed of blanks, empty ones dropped.
std::vector<std::string> split_list(std::string_view text, char separator = ',');

// A finite number, or a fraction "a/b" (sample distances are usually quoted as 1/256).
std::optional<double> parse_number(std::string_view text);

// "'<text>' is not a finite number".
std::string not_a_number(std::string_view text);

// "a,b,c" as numbers, each may be a fraction; the error names the first item that is not one and
// has `where` as its place.
Result<std::vector<double>> parse_numbers(std::string_view text, std::string where = {});

// `text` as valid UTF-8 of at most `max_bytes` bytes, for text read from files that reaches a
// JSON message (a label's name): each byte that does not belong to a valid sequence becomes '?',
// and the text is cut at the last whole character that fits.
std::string valid_utf8(std::string_view text, std::size_t max_bytes);

}  // namespace penumbra::base
