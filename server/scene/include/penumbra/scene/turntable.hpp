#pragma once

// A turntable movie's views: the volume turned on its stand under a fixed camera and fixed
// lights, which is the camera and the lights turned the other way about the view's up direction.

#include <penumbra/scene/camera.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/scene/light.hpp>

namespace penumbra::scene {

struct TurnedView {
    Camera camera;
    Light light;
};

// `camera` and `light` (a point light's position, a directional light's direction) turned together
// by `degrees` about the camera's up direction through its target.
[[nodiscard]] TurnedView turned_view(const Camera& camera, const Light& light, double degrees);

// How far frame `frame` of `frames` turns: a whole turn in equal steps (the last frame one step
// short of the first, so the movie loops), or, with `rock_degrees` above 0, a rocking sweep
// between -rock_degrees and +rock_degrees that starts and ends at the view itself.
[[nodiscard]] double turntable_degrees(int frame, int frames, double rock_degrees = 0.0);

// Frame `frame` of a turntable of `frames` frames: `request` with its camera and light turned by
// turntable_degrees.
[[nodiscard]] FrameRequest turntable_frame(const FrameRequest& request, int frame, int frames,
                                           double rock_degrees = 0.0);

}  // namespace penumbra::scene
