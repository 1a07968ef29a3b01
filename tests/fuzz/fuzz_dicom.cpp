// DICOM through DCMTK: the input as one file, and as the only file of a series folder.

#include "fuzz_files.hpp"

#include <penumbra/volume/volume.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace penumbra;
    static const std::filesystem::path series = [] {
        const auto folder = fuzz::scratch_folder() / "series";
        std::filesystem::create_directories(folder);
        return folder;
    }();
    volume::LoadOptions options;
    options.max_bytes = fuzz::fuzz_load_budget;
    options.within_available_memory = false;
    const auto file = fuzz::write_input("input.dcm", data, size);
    (void)volume::load_dicom(file, options);
    const auto in_series = fuzz::write_input("series/image", data, size);
    (void)volume::load_dicom(series, options);
    return 0;
}
