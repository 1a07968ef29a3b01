#pragma once

// Ray set-up shared by the CPU reference and shaders/include/ray.glsl.

#include <penumbra/scene/box.hpp>
#include <penumbra/scene/camera.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <limits>

namespace penumbra::optics {

// Entry and exit distances of a ray with a box (slab method). `hit` is false when the ray misses
// or the box lies behind the origin. A ray starting inside the box gets t_near = 0. The ray is
// taken into box space, where the box is axis-aligned; distances along it stay the same there.
struct BoxHit {
    double t_near = 0.0;
    double t_far = 0.0;
    bool hit = false;
};

inline BoxHit intersect_box(glm::dvec3 world_origin, glm::dvec3 world_direction,
                            const scene::Box& box) {
    const glm::dvec3 origin = box.to_box(world_origin);
    const glm::dvec3 direction = box.to_box(world_direction);
    double t_near = 0.0;
    double t_far = std::numeric_limits<double>::infinity();
    for (int axis = 0; axis < 3; ++axis) {
        const double inverse = 1.0 / direction[axis];  // ±inf for an axis-parallel ray
        double t0 = (box.min[axis] - origin[axis]) * inverse;
        double t1 = (box.max[axis] - origin[axis]) * inverse;
        if (t0 > t1) {
            std::swap(t0, t1);
        }
        // NaN (0 * inf: origin on a slab plane, ray parallel to it) must not widen the interval.
        if (t0 == t0) {
            t_near = glm::max(t_near, t0);
        }
        if (t1 == t1) {
            t_far = glm::min(t_far, t1);
        }
    }
    return BoxHit{t_near, t_far, t_near < t_far};
}

// The ray through the centre of pixel (x, y) of a width×height image, row 0 at the top.
inline glm::dvec3 pixel_ray_direction(const scene::CameraFrame& frame, int x, int y, int width,
                                      int height) {
    const double ndc_x = (x + 0.5) / width * 2.0 - 1.0;
    const double ndc_y = 1.0 - (y + 0.5) / height * 2.0;
    return glm::normalize(frame.forward + ndc_x * frame.right + ndc_y * frame.up);
}

// Where in each of its steps the ray of pixel (x, y) takes its sample, as a fraction of the step:
// the midpoint without jitter; with it, interleaved gradient noise over the pixels shifted by the
// golden ratio per pattern index (the refinement step). Computed in float exactly as
// ray_start_offset in shaders/include/ray.glsl, so the CPU reference samples where the GPU does.
inline double ray_start_offset(bool jitter, int x, int y, int pattern_index) {
    if (!jitter) {
        return 0.5;
    }
    const float along = static_cast<float>(x) * 0.06711056f + static_cast<float>(y) * 0.00583715f;
    const float scaled = 52.9829189f * (along - std::floor(along));
    const float noise = scaled - std::floor(scaled);
    const float shifted = noise + static_cast<float>(pattern_index) * 0.6180339887f;
    return static_cast<double>(shifted - std::floor(shifted));
}

// Samples of a ray segment [t_near, t_far]: the segment is cut into `count` equal steps of length
// `step` <= the requested sample distance, each sampled at the same fraction of the step
// (ray_start_offset). Every ray thus integrates
// exactly its own segment, whatever its length.
struct Marching {
    int count = 0;
    double step = 0.0;
};

inline Marching plan_marching(double t_near, double t_far, double sample_distance) {
    const double length = t_far - t_near;
    if (!(length > 0.0)) {
        return {};
    }
    const int count = static_cast<int>(glm::max(1.0, glm::ceil(length / sample_distance)));
    return {count, length / count};
}

}  // namespace penumbra::optics
