#pragma once

// File-name helpers shared by the loaders. Private to the volume module.

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>
#include <string_view>

namespace penumbra::volume::detail {

// The file name in lower case, for choosing a format by extension ("HEAD.NII.GZ" is NIfTI too).
inline std::string lower_file_name(const std::filesystem::path& path) {
    std::string name = path.filename().string();
    std::transform(name.begin(), name.end(), name.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return name;
}

inline bool has_suffix(std::string_view text, std::string_view suffix) {
    return text.size() >= suffix.size() && text.substr(text.size() - suffix.size()) == suffix;
}

// The file name without the first of `suffixes` it ends with (compared ignoring case), e.g. the
// stem "head" of "head.nii.gz" for {".nii.gz", ".nii"}; list longer suffixes first.
template <class Suffixes>
std::string strip_suffix(const std::filesystem::path& path, const Suffixes& suffixes) {
    std::string name = path.filename().string();
    const std::string lower = lower_file_name(path);
    for (std::string_view suffix : suffixes) {
        if (has_suffix(lower, suffix)) {
            return name.substr(0, name.size() - suffix.size());
        }
    }
    return name;
}

}  // namespace penumbra::volume::detail
