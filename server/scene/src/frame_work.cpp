#include "penumbra/scene/frame_work.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace penumbra::scene {

int samples_per_ray(const RenderSettings& settings, const Box& box) {
    return static_cast<int>(std::ceil(glm::length(box.size()) / settings.sample_distance)) + 1;
}

int bricks_per_ray(glm::ivec3 grid) {
    if (grid.x <= 0 || grid.y <= 0 || grid.z <= 0) {
        return 0;
    }
    return static_cast<int>(std::ceil(glm::length(glm::dvec3(grid)))) + 1;
}

double marched_samples(const RenderSettings& settings, int samples, const WorkContext& context) {
    if (!settings.empty_space_skipping || context.bricks_per_ray <= 0) {
        return samples;
    }
    const double visible = std::clamp(context.occupied_fraction, 0.0, 1.0);
    return std::min<double>(samples, std::ceil(samples * visible) + context.bricks_per_ray);
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

FrameWork estimate_work(const FrameRequest& request, const Box& box, int slab_samples,
                        const WorkContext& context) {
    const RenderSettings& s = request.settings;
    const double pixels = static_cast<double>(s.width) * s.height;
    const double light_texels =
            static_cast<double>(s.light_buffer.resolution) * s.light_buffer.resolution;
    FrameWork work;
    if (describe(s.mode).technique == Technique::half_angle_slicing) {
        work.slicing = s.light_buffer.slices * (pixels + light_texels);
    } else {
        const int samples = samples_per_ray(s, box);
        // Camera rays and the reference's shadow rays cross the same box and leap the same
        // bricks; the shadow ray's count is whole, as the loop it bounds.
        const double marched = marched_samples(s, samples, context);
        const int per_sample =
                iterations_per_sample(s, static_cast<int>(std::ceil(marched)), slab_samples);
        work.ray_casting = pixels * marched * static_cast<double>(per_sample);
        if (uses_light_buffer(s.mode)) {
            // Each light texel marches every slice's slab toward the far side of the box.
            const int light_samples = s.light_buffer.slices * slab_samples;
            work.light_buffer = light_texels * marched_samples(s, light_samples, context);
        }
    }
    if (request.refinement.step > 0) {
        work.refinement = work.interactive();
        work.ray_casting = work.light_buffer = work.slicing = 0.0;
    }
    return work;
}

}  // namespace penumbra::scene
