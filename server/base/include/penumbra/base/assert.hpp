#pragma once

namespace penumbra::base {

// A broken precondition inside Penumbra is a programmer mistake, not bad input: print where and
// abort. Untrusted input never reaches an assert; it gets an Error. The place comes from the
// macro (__FILE__, __LINE__, __func__) rather than std::source_location, which clang 14 (the fuzz
// build's compiler) cannot build with libstdc++ 12.
[[noreturn]] void assertion_failed(const char* expression, const char* message, const char* file,
                                   unsigned line, const char* function);

}  // namespace penumbra::base

#define PENUMBRA_ASSERT(condition, message)                                             \
    do {                                                                                \
        if (!(condition)) [[unlikely]] {                                                \
            ::penumbra::base::assertion_failed(#condition, message, __FILE__, __LINE__, \
                                               static_cast<const char*>(__func__));     \
        }                                                                               \
    } while (false)
