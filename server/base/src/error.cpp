#include <penumbra/base/assert.hpp>
#include <penumbra/base/result.hpp>

#include <cstdio>
#include <cstdlib>

namespace penumbra::base {

std::string Error::to_string() const {
    std::string text;
    if (!where.empty()) {
        text += where + ": ";
    }
    text += message;
    if (!code.empty()) {
        text += " [" + code + "]";
    }
    return text;
}

void assertion_failed(const char* expression, const char* message, std::source_location where) {
    std::fprintf(stderr, "%s:%u: %s: assertion '%s' failed: %s\n", where.file_name(), where.line(),
                 where.function_name(), expression, message);
    std::abort();
}

}  // namespace penumbra::base
