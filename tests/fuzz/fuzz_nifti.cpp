// load_nifti on any file: the nifti library's header reader, then the voxel data read by Penumbra
// (plain, or gzip when the bytes start with its magic, under the name a user would give it).

#include "fuzz_files.hpp"

#include <penumbra/volume/volume.hpp>

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace penumbra;
    const bool gzip = size >= 2 && data[0] == 0x1f && data[1] == 0x8b;
    const auto path = fuzz::write_input(gzip ? "input.nii.gz" : "input.nii", data, size);
    volume::LoadOptions options;
    options.max_bytes = fuzz::fuzz_load_budget;
    options.within_available_memory = false;
    (void)volume::load_nifti(path, options);
    return 0;
}
