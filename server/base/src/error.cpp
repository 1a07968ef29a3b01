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
    text += " [" + std::string(name_of(code)) + "]";
    return text;
}

void assertion_failed(const char* expression, const char* message, const char* file, unsigned line,
                      const char* function) {
    std::fprintf(stderr, "%s:%u: %s: assertion '%s' failed: %s\n", file, line, function, expression,
                 message);
    std::abort();
}

}  // namespace penumbra::base
