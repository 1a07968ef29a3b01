#include "frame_planner.hpp"

namespace penumbra::render {

FramePlan plan_frame(const scene::FrameRequest& request) {
    const scene::RenderSettings& s = request.settings;
    FramePlan plan;
    plan.half_angle = s.mode == scene::Mode::half_angle;
    plan.needs_light_buffer = scene::uses_light_buffer(s.mode);
    plan.needs_light_view = plan.needs_light_buffer || plan.half_angle;

    RaycastVariant& v = plan.variant;
    v.stage = s.stage;
    v.extinction = s.compositing == scene::Compositing::extinction;
    v.phong = scene::uses_gradients(s);
    v.empty_space_skipping = s.empty_space_skipping;
    switch (s.mode) {
        case scene::Mode::sbrc: v.shadows = Shadows::light_buffer; break;
        case scene::Mode::sbrc_shell:
            v.shadows = Shadows::light_buffer;
            v.scattering = Scattering::shell;
            break;
        case scene::Mode::sbrc_cone:
            v.shadows = Shadows::light_buffer;
            v.scattering = Scattering::cone;
            break;
        case scene::Mode::reference: v.shadows = Shadows::rays; break;
        default: break;
    }
    v.local_light_lookup = v.shadows == Shadows::light_buffer &&
                           s.light_buffer.lookup == scene::LightLookup::local;
    // Only code that reads the light's position or direction per sample needs to know its kind.
    const bool reads_light = v.phong || v.shadows != Shadows::none || plan.half_angle;
    v.point_light = reads_light && request.light.type == scene::LightType::point;
    return plan;
}

}  // namespace penumbra::render
