#pragma once

#include <source_location>

namespace penumbra::base {

// A broken precondition inside Penumbra is a programmer mistake, not bad input: print where and
// abort. Untrusted input never reaches an assert; it gets an Error.
[[noreturn]] void assertion_failed(const char* expression, const char* message,
                                   std::source_location where = std::source_location::current());

}  // namespace penumbra::base

#define PENUMBRA_ASSERT(condition, message)                                   \
    do {                                                                      \
        if (!(condition)) [[unlikely]] {                                      \
            ::penumbra::base::assertion_failed(#condition, message);          \
        }                                                                     \
    } while (false)
