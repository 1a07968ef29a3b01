#pragma once

#include <penumbra/base/result.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace penumbra::base {

// Compares two secrets (tokens, keys) in a time that depends on their length only, never on where
// they first differ, so that a client timing its refusals learns nothing of the secret's bytes.
bool same_secret(std::string_view a, std::string_view b);

// A secret from `file` where one is named, else from the environment variable `variable`; empty
// when neither is given (a secret is never a command-line value, which every user of the machine
// can read). Trailing blanks are no part of it: editors and `echo` end a file with a newline. A
// secret that is empty after all is an error; errors name `file_where` (the option that named the
// file) or the variable.
Result<std::string> read_secret(const std::optional<std::filesystem::path>& file,
                                const char* variable, const std::string& file_where);

}  // namespace penumbra::base
