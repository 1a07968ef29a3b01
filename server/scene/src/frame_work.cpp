#include "penumbra/scene/frame_work.hpp"

#include <glm/geometric.hpp>

#include <cmath>

namespace penumbra::scene {

int samples_per_ray(const RenderSettings& settings, const Box& box) {
    return static_cast<int>(std::ceil(glm::length(box.size()) / settings.sample_distance)) + 1;
}

int iterations_per_sample(const RenderSettings& settings, int samples_per_ray, int slab_samples) {
    const int local_lookup =
            settings.light_buffer.lookup == LightLookup::local ? 1 + slab_samples : 0;
    const ModeInfo& mode = describe(settings.mode);
    int iterations = mode.cost.fixed + mode.cost.per_shell_ring * settings.scattering.shell_rings;
    switch (mode.shadows) {
        case ShadowKind::none:
            break;
        case ShadowKind::light_buffer:
            iterations += local_lookup;
            break;
        case ShadowKind::rays:
            iterations += samples_per_ray;
            break;
    }
    return iterations;
}

FrameWork estimate_work(const FrameRequest& request, const Box& box, int slab_samples) {
    const RenderSettings& s = request.settings;
    const double pixels = static_cast<double>(s.width) * s.height;
    const double light_texels =
            static_cast<double>(s.light_buffer.resolution) * s.light_buffer.resolution;
    FrameWork work;
    if (describe(s.mode).technique == Technique::half_angle_slicing) {
        work.slicing = s.light_buffer.slices * (pixels + light_texels);
        return work;
    }
    const int samples = samples_per_ray(s, box);
    work.ray_casting =
            pixels * samples * static_cast<double>(iterations_per_sample(s, samples, slab_samples));
    if (uses_light_buffer(s.mode)) {
        work.light_buffer = light_texels * s.light_buffer.slices * slab_samples;
    }
    return work;
}

}  // namespace penumbra::scene
