// parse_transfer_function on any text (a --tf file of `penumbra render`), with and without a data
// range; a function it accepts must bake without tripping an assertion.

#include <penumbra/protocol/scene_json.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <utility>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace penumbra;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    for (const auto& range : {std::optional<std::pair<double, double>>{},
                              std::optional<std::pair<double, double>>{{-1024.0, 3071.0}}}) {
        auto tf = protocol::parse_transfer_function(text, range, "tf.json");
        if (tf.ok()) {
            (void)scene::bake(*tf, 256);
        }
    }
    return 0;
}
