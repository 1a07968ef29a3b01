#include "penumbra/optics/light_slicing.hpp"

#include <penumbra/scene/frame_request.hpp>

#include <glm/common.hpp>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra::optics {
namespace {

// Any unit vector not parallel to `axis`, for building a view basis.
glm::dvec3 up_for(glm::dvec3 axis) {
    return std::abs(axis.z) < 0.9 ? glm::dvec3(0.0, 0.0, 1.0) : glm::dvec3(0.0, 1.0, 0.0);
}

}  // namespace

std::array<glm::dvec3, 8> box_corners(const scene::Box& box) {
    std::array<glm::dvec3, 8> corners;
    for (int i = 0; i < 8; ++i) {
        corners[i] = box.to_world({(i & 1) ? box.max.x : box.min.x, (i & 2) ? box.max.y : box.min.y,
                                   (i & 4) ? box.max.z : box.min.z});
    }
    return corners;
}

glm::dvec3 light_travel_direction(const scene::Light& light, const scene::Box& box) {
    if (light.type == scene::LightType::point) {
        return glm::normalize(box.centre() - light.position);
    }
    return -glm::normalize(light.direction);
}

double LightSlicing::index(glm::dvec3 world) const {
    return count * (glm::dot(travel, world) - min) / (max - min);
}

LightSlicing make_light_slicing(const scene::Box& box, glm::dvec3 travel, int count) {
    LightSlicing slicing;
    slicing.travel = travel;
    slicing.count = count;
    slicing.min = std::numeric_limits<double>::infinity();
    slicing.max = -std::numeric_limits<double>::infinity();
    for (const glm::dvec3& corner : box_corners(box)) {
        const double d = glm::dot(travel, corner);
        slicing.min = std::min(slicing.min, d);
        slicing.max = std::max(slicing.max, d);
    }
    return slicing;
}

std::vector<glm::dvec3> slice_polygon(const scene::Box& box, glm::dvec3 normal, double d) {
    const auto corners = box_corners(box);
    // The 12 edges as corner-index pairs differing in one bit.
    static constexpr int edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                         {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    std::vector<glm::dvec3> points;
    for (const auto& edge : edges) {
        const glm::dvec3 a = corners[edge[0]];
        const glm::dvec3 b = corners[edge[1]];
        const double da = glm::dot(normal, a) - d;
        const double db = glm::dot(normal, b) - d;
        if ((da < 0.0) == (db < 0.0) || da == db) {
            continue;  // both on one side (a plane through a corner is caught by the next edge)
        }
        const glm::dvec3 p = a + (b - a) * (da / (da - db));
        // A plane through a corner meets up to three edges there; keep the point once.
        const bool duplicate = std::any_of(points.begin(), points.end(), [&](const glm::dvec3& q) {
            return glm::length(q - p) < 1e-12;
        });
        if (!duplicate) {
            points.push_back(p);
        }
    }
    if (points.size() < 3) {
        return {};
    }
    glm::dvec3 centroid(0.0);
    for (const auto& p : points) {
        centroid += p;
    }
    centroid /= static_cast<double>(points.size());
    const glm::dvec3 u = glm::normalize(glm::cross(normal, up_for(normal)));
    const glm::dvec3 v = glm::cross(normal, u);
    std::sort(points.begin(), points.end(), [&](const glm::dvec3& a, const glm::dvec3& b) {
        return std::atan2(glm::dot(a - centroid, v), glm::dot(a - centroid, u)) <
               std::atan2(glm::dot(b - centroid, v), glm::dot(b - centroid, u));
    });
    return points;
}

LayerBlend layer_blend(double index, int count) {
    const double position = glm::clamp(index - 0.5, 0.0, static_cast<double>(count - 1));
    const int lower = static_cast<int>(std::floor(position));
    const int upper = std::min(lower + 1, count - 1);
    return {lower, upper, position - lower};
}

base::Result<LightView> make_light_view(const scene::Light& light, const scene::Box& box) {
    const glm::dvec3 centre = box.centre();
    const auto corners = box_corners(box);
    LightView out;
    if (light.type == scene::LightType::directional) {
        const glm::dvec3 travel = light_travel_direction(light, box);
        const double radius = 0.5 * glm::length(box.size());
        const glm::dmat4 view =
                glm::lookAt(centre - travel * (2.0 * radius), centre, up_for(travel));
        double x0 = std::numeric_limits<double>::infinity();
        double y0 = x0;
        double x1 = -x0;
        double y1 = -x0;
        for (const auto& corner : corners) {
            const glm::dvec4 p = view * glm::dvec4(corner, 1.0);
            x0 = std::min(x0, p.x);
            x1 = std::max(x1, p.x);
            y0 = std::min(y0, p.y);
            y1 = std::max(y1, p.y);
        }
        // Depth covers the box with room to spare: the eye is 2 radii from the centre.
        out.view_projection = glm::ortho(x0, x1, y0, y1, radius * 0.5, radius * 3.5) * view;
    } else {
        // Checked first: at the centre itself the view below would be NaN, not an error.
        if (box.contains(light.position)) {
            return base::make_error(base::ErrorCode::unsupported_light,
                                    "a point light inside or beside the volume cannot be "
                                    "used by the light-buffer modes; move it outside the box",
                                    "light.position");
        }
        const glm::dvec3 axis = glm::normalize(centre - light.position);
        const glm::dmat4 view = glm::lookAt(light.position, centre, up_for(axis));
        double near = std::numeric_limits<double>::infinity();
        double far = 0.0;
        double tangent = 0.0;
        for (const auto& corner : corners) {
            const glm::dvec4 p = view * glm::dvec4(corner, 1.0);
            const double depth = -p.z;
            if (depth <= 1e-6) {
                return base::make_error(base::ErrorCode::unsupported_light,
                                        "a point light inside or beside the volume cannot be "
                                        "used by the light-buffer modes; move it outside the box",
                                        "light.position");
            }
            near = std::min(near, depth);
            far = std::max(far, depth);
            tangent = std::max({tangent, std::abs(p.x) / depth, std::abs(p.y) / depth});
        }
        const double fov = 2.0 * std::atan(tangent);
        if (fov >= glm::radians(170.0)) {
            return base::make_error(base::ErrorCode::unsupported_light,
                                    "the point light is too close to the volume for one "
                                    "perspective light view (needs a field of view under 170°)",
                                    "light.position");
        }
        out.view_projection = glm::perspective(fov, 1.0, near * 0.5, far * 1.5) * view;
        out.perspective = true;
        out.position = light.position;
    }
    out.inverse_view_projection = glm::inverse(out.view_projection);
    return out;
}

glm::dvec2 light_uv(const LightView& view, glm::dvec3 world) {
    const glm::dvec4 clip = view.view_projection * glm::dvec4(world, 1.0);
    return glm::dvec2(clip.x, clip.y) / clip.w * 0.5 + 0.5;
}

int resolve_slab_samples(const LightSlicing& slicing, glm::dvec3 voxel_size, int requested) {
    if (requested > 0) {
        return std::min(requested, scene::kMaxSlabSamples);
    }
    const double voxel = std::min({voxel_size.x, voxel_size.y, voxel_size.z});
    if (!(voxel > 0.0)) {
        return 1;
    }
    const double per_voxel = std::ceil(slicing.spacing() / voxel - 1e-9);
    return static_cast<int>(std::clamp(per_voxel, 1.0, double(scene::kMaxSlabSamples)));
}

double compensated_transmittance(double alpha, double compensation) {
    const double a = glm::clamp(alpha, 0.0, 1.0);
    if (a >= 1.0) {
        return 0.0;  // an opaque slice stays opaque: 0 · (1 + a)^n would be 0 · inf for large n
    }
    return std::min(1.0, (1.0 - a) * std::pow(1.0 + a, compensation));
}

}  // namespace penumbra::optics
