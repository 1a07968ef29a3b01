#include "penumbra/scene/frame_work.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

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

namespace {

bool skips(const RenderSettings& settings, const WorkContext& context) {
    return settings.empty_space_skipping && bricks_per_ray(context.brick_grid) > 0;
}

// The most any one line can have of the visible bricks: a bound on its length inside them, and
// on how many of them it crosses.
struct VisibleStretch {
    double length = 0.0;
    double bricks = 0.0;
};

VisibleStretch longest_visible_stretch(const Box& box, const WorkContext& context,
                                       const std::optional<OccupiedBricks>& known) {
    const glm::ivec3 grid = context.brick_grid;
    const OccupiedBricks occupied = known.value_or(OccupiedBricks{
            static_cast<std::int64_t>(grid.x) * grid.y * grid.z, glm::ivec3(0), grid - 1});
    if (occupied.count <= 0) {
        return {};
    }
    const glm::dvec3 brick = box.size() / glm::dvec3(grid);
    const glm::ivec3 block = occupied.last - occupied.first + 1;
    const auto bricks =
            static_cast<double>(std::min<std::int64_t>(occupied.count, bricks_per_ray(block)));
    const double length =
            std::min(bricks * glm::length(brick), glm::length(glm::dvec3(block) * brick));
    return {length, bricks};
}

}  // namespace

double marched_samples(const RenderSettings& settings, int samples, const Box& box,
                       const WorkContext& context) {
    if (!skips(settings, context)) {
        return samples;
    }
    const VisibleStretch visible = longest_visible_stretch(box, context, context.occupied);
    const double in_visible =
            std::ceil(visible.length / settings.sample_distance) + 1.0 + visible.bricks;
    const double leaps = bricks_per_ray(context.brick_grid);
    return std::min<double>(samples, in_visible + leaps);
}

double marched_slab_samples(const RenderSettings& settings, int slab_samples, const Box& box,
                            const WorkContext& context) {
    const int slices = settings.light_buffer.slices;
    const double every_slab = static_cast<double>(slices) * slab_samples;
    if (!skips(settings, context)) {
        return every_slab;
    }
    const VisibleStretch visible =
            longest_visible_stretch(box, context, context.occupied_for_light);
    const glm::dvec3 size = box.size();
    const double shortest_slab = std::min({size.x, size.y, size.z}) / slices;
    const double sampled_slabs = std::min<double>(
            slices, std::ceil(visible.length / shortest_slab) + 2.0 * visible.bricks);
    return std::min(every_slab, sampled_slabs * slab_samples + slices);
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
        // The reference's shadow rays are lines through the same box at the same sample distance
        // as the camera rays, so the same bound holds for them; their count is whole, as the
        // loop it bounds.
        const double marched = marched_samples(s, samples, box, context);
        const int per_sample =
                iterations_per_sample(s, static_cast<int>(std::ceil(marched)), slab_samples);
        work.ray_casting = pixels * marched * static_cast<double>(per_sample);
        if (uses_light_buffer(s.mode)) {
            // Each light texel marches the slices' slabs toward the far side of the box.
            work.light_buffer = light_texels * marched_slab_samples(s, slab_samples, box, context);
        }
    }
    if (request.refinement.step > 0) {
        work.refinement = work.interactive();
        work.ray_casting = work.light_buffer = work.slicing = 0.0;
    }
    return work;
}

}  // namespace penumbra::scene
