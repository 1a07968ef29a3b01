// quality::parse_table on any text (the accuracy table `penumbra serve --quality-table` reads).

#include <penumbra/quality/table_json.hpp>

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    (void)penumbra::quality::parse_table(text, "table.json");
    return 0;
}
