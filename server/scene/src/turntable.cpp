#include <penumbra/scene/turntable.hpp>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cmath>

namespace penumbra::scene {

TurnedView turned_view(const Camera& camera, const Light& light, double degrees) {
    const glm::dquat rotation = glm::angleAxis(glm::radians(degrees), glm::normalize(camera.up));
    const auto turn = [&](glm::dvec3 v) { return rotation * v; };
    TurnedView view{camera, light};
    view.camera.eye = camera.target + turn(camera.eye - camera.target);
    view.light.direction = turn(light.direction);
    view.light.position = camera.target + turn(light.position - camera.target);
    return view;
}

double turntable_degrees(int frame, int frames, double rock_degrees) {
    const double phase = frames > 0 ? double(frame) / double(frames) : 0.0;
    if (rock_degrees > 0.0) {
        return rock_degrees * std::sin(glm::two_pi<double>() * phase);
    }
    return 360.0 * phase;
}

FrameRequest turntable_frame(const FrameRequest& request, int frame, int frames,
                             double rock_degrees) {
    const TurnedView view = turned_view(request.camera, request.light,
                                        turntable_degrees(frame, frames, rock_degrees));
    FrameRequest turned = request;
    turned.camera = view.camera;
    turned.light = view.light;
    return turned;
}

}  // namespace penumbra::scene
