// parse_request and request_id_of on any text a client can send; an accepted `set` is applied, and
// the state it produces must read back through apply_patch (state_to_json is what clients get).

#include <penumbra/base/assert.hpp>
#include <penumbra/base/error_code.hpp>
#include <penumbra/protocol/messages.hpp>
#include <penumbra/protocol/scene_json.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <variant>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace penumbra;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const protocol::Limits limits;
    (void)protocol::request_id_of(text);
    const auto request = protocol::parse_request(text, limits);
    if (!request.ok()) {
        const base::ErrorCode code = request.error().code;
        PENUMBRA_ASSERT(static_cast<std::size_t>(code) < base::kErrorCodeNames.size() &&
                                code != base::ErrorCode::internal_error &&
                                !request.error().where.empty(),
                        "a refused request names a client's error and its field");
        return 0;
    }
    if (const auto* set = std::get_if<protocol::Set>(&request->message)) {
        scene::State state;
        state.frame.transfer_function = scene::preset("grey_ramp").value();
        const auto applied = protocol::apply_patch(set->patch, state, limits);
        if (applied.ok()) {
            scene::State again;
            again.frame.transfer_function = scene::preset("grey_ramp").value();
            PENUMBRA_ASSERT(
                    protocol::apply_patch(protocol::state_to_json(state), again, limits).ok(),
                    "the state a patch produced reads back as a patch");
        }
    }
    return 0;
}
