#include "penumbra/base/data_dir.hpp"

#include <cstdlib>
#include <system_error>

namespace penumbra::base {

std::optional<std::filesystem::path> data_dir(std::string_view part) {
    std::error_code error;
    const std::filesystem::path binary = std::filesystem::read_symlink("/proc/self/exe", error);
    if (error) {
        return std::nullopt;
    }
    for (std::filesystem::path folder = binary.parent_path(); !folder.empty();
         folder = folder.parent_path()) {
        const std::filesystem::path candidate = folder / "share" / "penumbra" / part;
        if (std::filesystem::is_directory(candidate, error)) {
            return candidate;
        }
        if (folder == folder.root_path()) {
            break;
        }
    }
    return std::nullopt;
}

std::optional<std::filesystem::path> user_cache_dir() {
    if (const char* cache = std::getenv("XDG_CACHE_HOME"); cache != nullptr && *cache != '\0') {
        return std::filesystem::path(cache) / "penumbra";
    }
    if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
        return std::filesystem::path(home) / ".cache" / "penumbra";
    }
    return std::nullopt;
}

std::optional<std::filesystem::path> demo_data_dir() {
    if (const auto cache = user_cache_dir()) {
        return *cache / "volumes";
    }
    return std::nullopt;
}

std::optional<std::filesystem::path> demo_ct_path() {
    std::error_code ec;
    if (const auto folder = demo_data_dir()) {
        std::filesystem::path path = *folder / "cranium_ct.nrrd";
        if (std::filesystem::is_regular_file(path, ec)) {
            return path;
        }
    }
    return std::nullopt;
}

}  // namespace penumbra::base
