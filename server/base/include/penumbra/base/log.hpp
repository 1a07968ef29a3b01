#pragma once

#include <string_view>

namespace penumbra::base {

enum class LogLevel { debug, info, warning, error };

// One line per event on stderr: "<ISO time> <level> <component>: <message>". Thread-safe.
void log(LogLevel level, std::string_view component, std::string_view message);

void set_log_level(LogLevel minimum);

inline void log_info(std::string_view component, std::string_view message) {
    log(LogLevel::info, component, message);
}

inline void log_warning(std::string_view component, std::string_view message) {
    log(LogLevel::warning, component, message);
}

inline void log_error(std::string_view component, std::string_view message) {
    log(LogLevel::error, component, message);
}

inline void log_debug(std::string_view component, std::string_view message) {
    log(LogLevel::debug, component, message);
}

}  // namespace penumbra::base
