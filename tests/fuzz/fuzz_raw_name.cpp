// Raw volumes: the file name carries the format (name_XxYxZ_type.raw[.gz]). The input's first
// line is the file name, the rest the file's bytes; load_volume chooses the loader by name.

#include "fuzz_files.hpp"

#include <penumbra/volume/volume.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <system_error>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace penumbra;
    const auto* end = data + size;
    const auto* newline = std::find(data, end, std::uint8_t{'\n'});
    std::string name(reinterpret_cast<const char*>(data),
                     std::min<std::size_t>(static_cast<std::size_t>(newline - data), 200));
    // A name, not a path: no separators, no NUL, not "." or "..".
    std::replace(name.begin(), name.end(), '/', '_');
    std::replace(name.begin(), name.end(), '\0', '_');
    if (name.empty() || name == "." || name == "..") {
        name = "_";
    }
    const auto* body = newline == end ? end : newline + 1;
    const auto path = fuzz::write_input(name, body, static_cast<std::size_t>(end - body));
    volume::LoadOptions options;
    options.max_bytes = fuzz::fuzz_load_budget;
    options.within_available_memory = false;
    (void)volume::load_raw(path, options);
    (void)volume::load_volume(path, options);
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
    return 0;
}
