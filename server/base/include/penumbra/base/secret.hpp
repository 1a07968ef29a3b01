#pragma once

#include <string_view>

namespace penumbra::base {

// Compares two secrets (tokens, keys) in a time that depends on their length only, never on where
// they first differ, so that a client timing its refusals learns nothing of the secret's bytes.
bool same_secret(std::string_view a, std::string_view b);

}  // namespace penumbra::base
