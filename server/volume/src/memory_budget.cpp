#include "memory_budget.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace penumbra::volume {
namespace {

std::string mebibytes(std::uint64_t bytes) {
    char text[48];
    std::snprintf(text, sizeof text, "%.1f MiB", static_cast<double>(bytes) / (1 << 20));
    return text;
}

}  // namespace

std::optional<std::uint64_t> available_memory() {
    std::ifstream meminfo("/proc/meminfo");
    std::string line;
    while (std::getline(meminfo, line)) {
        constexpr std::string_view key = "MemAvailable:";
        if (line.starts_with(key)) {
            std::istringstream fields(line.substr(key.size()));
            std::uint64_t kibibytes = 0;
            if (fields >> kibibytes) {
                return kibibytes * 1024;
            }
        }
    }
    return std::nullopt;
}

namespace detail {

base::Status check_budget(std::uint64_t bytes, const std::string& what,
                          const std::filesystem::path& path, const LoadOptions& options) {
    if (bytes > options.max_bytes) {
        return base::make_error(base::ErrorCode::too_large,
                                what + " needs " + mebibytes(bytes) +
                                        " in memory, more than the load limit of " +
                                        mebibytes(options.max_bytes),
                                path.string());
    }
    if (options.within_available_memory) {
        const auto available = available_memory();
        if (available && bytes > *available) {
            return base::make_error(base::ErrorCode::too_large,
                                    what + " needs " + mebibytes(bytes) +
                                            " in memory, more than the machine has available (" +
                                            mebibytes(*available) + ")",
                                    path.string());
        }
    }
    return base::Ok{};
}

}  // namespace detail
}  // namespace penumbra::volume
