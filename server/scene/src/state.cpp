#include <penumbra/scene/frame_request.hpp>

#include "penumbra/scene/frame_request.hpp"

namespace penumbra::scene {

base::Status validate(const State& state, const Limits& limits) {
    for (const Setting* setting : kSettings) {
        if (setting->held() && !setting->in_frame()) {
            if (auto status = validate_value(*setting, setting->read(state), limits); !status) {
                return status;
            }
        }
    }
    return validate(state.frame, limits);
}

}  // namespace penumbra::scene
