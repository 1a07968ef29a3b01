#pragma once

#include "raycast_pass.hpp"

#include <penumbra/scene/frame_request.hpp>

namespace penumbra::render {

// "Simulate only the effects a scene calls for": which passes a frame runs and which shader
// variant each uses. No light buffer unless the mode casts light-buffer shadows, no gradients
// unless shading needs them, shadow rays only for the reference.
struct FramePlan {
    bool half_angle = false;        // slice-based instead of ray-cast
    bool needs_light_view = false;  // the light's view-projection (light buffer or half-angle)
    bool needs_light_buffer = false;
    RaycastVariant variant;  // the ray caster's, or the half-angle passes' defines
};

FramePlan plan_frame(const scene::FrameRequest& request);

}  // namespace penumbra::render
