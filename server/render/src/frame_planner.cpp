#include "frame_planner.hpp"

namespace penumbra::render {

FramePlan plan_frame(const scene::FrameRequest& request) {
    const scene::RenderSettings& s = request.settings;
    FramePlan plan;
    const scene::ModeInfo& mode = scene::describe(s.mode);
    plan.half_angle = mode.technique == scene::Technique::half_angle_slicing;
    plan.needs_light_buffer = scene::uses_light_buffer(s.mode);
    plan.needs_light_view = scene::uses_light_view(s.mode);

    RaycastVariant& v = plan.variant;
    v.stage = s.stage;
    v.extinction = s.compositing == scene::Compositing::extinction;
    v.reconstruction = s.reconstruction;
    v.phong = scene::uses_gradients(s);
    v.empty_space_skipping = s.empty_space_skipping;
    // The ray caster's marches and the light buffer's slabs; half-angle classifies a slice alone.
    v.preintegration = s.preintegration && !plan.half_angle;
    v.labels = request.labels.shown();
    v.shadows = mode.shadows;
    v.scattering = mode.scattering;
    v.local_light_lookup = v.shadows == Shadows::light_buffer &&
                           s.light_buffer.lookup == scene::LightLookup::local;
    // Only code that reads the light's position or direction per sample needs to know its kind.
    const bool reads_light = v.phong || v.shadows != Shadows::none || plan.half_angle;
    v.point_light = reads_light && request.light.type == scene::LightType::point;
    return plan;
}

}  // namespace penumbra::render
