#pragma once

// The memory budget of a load and the guard that turns a failed allocation into an Error. Private
// to the volume module.

#include <penumbra/base/result.hpp>
#include <penumbra/volume/volume.hpp>

#include <cstdint>
#include <filesystem>
#include <new>
#include <stdexcept>
#include <string>

namespace penumbra::volume::detail {

// Refuses a load that would hold `bytes` (what `what` describes, e.g. "181x217x181 int16 kept as
// float32") beyond options.max_bytes or, when asked, beyond the memory available now.
base::Status check_budget(std::uint64_t bytes, const std::string& what,
                          const std::filesystem::path& path, const LoadOptions& options);

// Runs a loader; an allocation it could not get (std::bad_alloc, std::length_error from a vector
// too large for the address space) becomes an "out_of_memory" Error naming the file.
template <class Load>
base::Result<Volume> guard_allocation(const std::filesystem::path& path, Load&& load) {
    try {
        return load();
    } catch (const std::bad_alloc&) {
        return base::make_error(base::ErrorCode::out_of_memory,
                                "not enough memory to load the volume", path.string());
    } catch (const std::length_error&) {
        return base::make_error(base::ErrorCode::out_of_memory,
                                "the volume is too large for this machine", path.string());
    }
}

}  // namespace penumbra::volume::detail
