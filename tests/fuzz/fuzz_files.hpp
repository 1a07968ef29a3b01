#pragma once

// For fuzz targets whose parser reads files: one private folder per process, removed at exit, and
// the input written to a file in it.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>

namespace penumbra::fuzz {

inline const std::filesystem::path& scratch_folder() {
    static const std::filesystem::path folder = [] {
        std::string pattern = (std::filesystem::temp_directory_path() / "penumbra-fuzz-XXXXXX");
        if (mkdtemp(pattern.data()) == nullptr) {
            std::abort();
        }
        std::atexit([] {
            std::error_code ignored;
            std::filesystem::remove_all(scratch_folder(), ignored);
        });
        return std::filesystem::path(pattern);
    }();
    return folder;
}

inline std::filesystem::path write_input(std::string_view name, const std::uint8_t* data,
                                         std::size_t size) {
    const auto path = scratch_folder() / name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!out) {
        std::abort();
    }
    return path;
}

// What a fuzzed load may allocate: far below libFuzzer's -rss_limit_mb, so that an input the
// budget lets through never looks like a leak or a memory bomb.
inline constexpr std::uint64_t fuzz_load_budget = std::uint64_t{64} << 20;

}  // namespace penumbra::fuzz
