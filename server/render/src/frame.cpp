#include "penumbra/render/frame.hpp"

namespace penumbra::render {

std::string_view to_string(LightBufferState state) {
    switch (state) {
        case LightBufferState::none:
            return "none";
        case LightBufferState::built:
            return "built";
        case LightBufferState::reused:
            return "reused";
    }
    return "none";
}

double FrameReport::gpu_total_ms() const {
    double total = 0.0;
    for (const auto& pass : passes) {
        total += pass.gpu_ms;
    }
    return total;
}

}  // namespace penumbra::render
