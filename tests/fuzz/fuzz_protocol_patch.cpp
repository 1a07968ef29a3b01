// apply_patch on any text (the `set` patch as the session applies it), from a state that earlier
// patches may have changed; on error the state must be unchanged, on success it must read back.

#include <penumbra/base/assert.hpp>
#include <penumbra/protocol/scene_json.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace penumbra;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const protocol::Limits limits;
    // A session drawing a label map of three labels, so that `labels` patches reach their checks.
    const std::vector<scene::LabelStyle> styles{{.id = 1}, {.id = 2}, {.id = 45}};
    scene::State state;
    state.frame.transfer_function = scene::preset("mri_skin").value();
    state.frame.labels.styles = styles;
    const std::string before = protocol::state_to_json(state);
    const auto applied = protocol::apply_patch(text, state, limits);
    if (!applied.ok()) {
        PENUMBRA_ASSERT(protocol::state_to_json(state) == before,
                        "a refused patch leaves the state as it was");
        return 0;
    }
    scene::State again;
    again.frame.transfer_function = scene::preset("grey_ramp").value();
    again.frame.labels.styles = styles;
    PENUMBRA_ASSERT(protocol::apply_patch(protocol::state_to_json(state), again, limits).ok(),
                    "the state a patch produced reads back as a patch");
    return 0;
}
