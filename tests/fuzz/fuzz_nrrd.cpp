// load_nrrd on any file: the header parser, then whatever data the header points at. Detached
// headers find a raw and a gzip data file beside them (data.raw, data.raw.gz, 4 KiB each).

#include "fuzz_files.hpp"

#include <penumbra/volume/volume.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace {

void write_data_files() {
    static const bool written = [] {
        std::array<std::uint8_t, 4096> bytes{};
        for (std::size_t i = 0; i < bytes.size(); ++i) {
            bytes[i] = static_cast<std::uint8_t>(i * 7);
        }
        penumbra::fuzz::write_input("data.raw", bytes.data(), bytes.size());
        // gzip of 4096 zero bytes (gzip -9 -n).
        static constexpr std::array<std::uint8_t, 38> zeros_gz{
                0x1f, 0x8b, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x03, 0xed, 0xc1, 0x01,
                0x0d, 0x00, 0x00, 0x00, 0xc2, 0xa0, 0xf7, 0x4f, 0x6d, 0x0f, 0x07, 0x14, 0x00,
                0x00, 0x00, 0xf0, 0x6e, 0x11, 0x00, 0x1c, 0xc7, 0x00, 0x10, 0x00, 0x00};
        penumbra::fuzz::write_input("data.raw.gz", zeros_gz.data(), zeros_gz.size());
        return true;
    }();
    (void)written;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace penumbra;
    write_data_files();
    const auto path = fuzz::write_input("input.nhdr", data, size);
    volume::LoadOptions options;
    options.max_bytes = fuzz::fuzz_load_budget;
    options.within_available_memory = false;
    (void)volume::load_nrrd(path, options);
    return 0;
}
