#include "penumbra/base/data_dir.hpp"

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

}  // namespace penumbra::base
