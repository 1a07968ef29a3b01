#pragma once

// The region drawn: the volume's box cut down by the user's cut (scene::Cut), a convex set, so
// that a ray's interval through it is all a pass needs. Mirrored line for line by
// shaders/include/region.glsl, which every pass asks; a new shape of cut is a set of half-spaces
// added in region_of here and nowhere else.

#include <penumbra/optics/ray.hpp>
#include <penumbra/scene/box.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <vector>

namespace penumbra::optics {

// The points p of world space with dot(normal, p) + offset >= 0.
struct HalfSpace {
    glm::dvec3 normal{0.0};
    double offset = 0.0;

    bool operator==(const HalfSpace&) const = default;
};

// The crop box's six faces and the clip planes.
inline constexpr int kMaxHalfSpaces = 6 + scene::kMaxClipPlanes;

// Who asks. Camera rays always see the cut. What carries light (the light-buffer builders, the
// local lookup's march through a slab, the reference's shadow rays, half-angle's light pass) sees
// it only when the cut tissue casts no shadow; else it sees the whole box.
enum class RegionUser { camera, light };

struct Region {
    scene::Box box;
    std::array<HalfSpace, kMaxHalfSpaces> half_spaces{};
    int count = 0;        // the half-spaces camera rays clip by: the first `count`
    int light_count = 0;  // those the light clips by: `count`, or 0 when the cut casts shadows

    [[nodiscard]] int count_for(RegionUser user) const {
        return user == RegionUser::camera ? count : light_count;
    }

    bool operator==(const Region&) const = default;
};

// The region of a volume drawn in `box`, placed in patient space by `placement`, under `cut`.
[[nodiscard]] Region region_of(const scene::Box& box, const scene::Cut& cut,
                               const scene::PatientPlacement& placement);

// Whether the part of the volume's box between box-space corners `low` and `high` (a brick) lies
// wholly beyond one of the half-spaces `user` clips by, so that nothing of it is drawn (or lit).
// A part that only several half-spaces together leave out counts as not outside: what this calls
// outside may be skipped, never more.
[[nodiscard]] bool outside_region(const Region& region, glm::dvec3 low, glm::dvec3 high,
                                  RegionUser user);

// The part of the convex polygon `polygon` (vertices in order around it, in one plane; a slice
// polygon) that lies in the half-spaces `user` clips by: still convex and in order, so a triangle
// fan draws it; empty when less than a triangle is left. So the slicing passes rasterise only
// what the region keeps.
[[nodiscard]] std::vector<glm::dvec3> clip_polygon(const Region& region, RegionUser user,
                                                   std::vector<glm::dvec3> polygon);

// The interval [t_near, t_far] of the line origin + t * direction, narrowed to where it lies deeper
// than `depth` inside each of the first `count` half-spaces of `region` (depth 0: in them; depth d:
// every point within d of it is in them too). t_near >= t_far when it lies in none of it.
struct LineInterval {
    double t_near = 0.0;
    double t_far = 0.0;
};

[[nodiscard]] inline LineInterval clip_to_half_spaces(const Region& region, int count,
                                                      glm::dvec3 origin, glm::dvec3 direction,
                                                      LineInterval line, double depth) {
    for (int i = 0; i < count; ++i) {
        const HalfSpace& h = region.half_spaces[static_cast<std::size_t>(i)];
        const double along = glm::dot(h.normal, direction);
        const double at = glm::dot(h.normal, origin) + h.offset - depth;
        if (along == 0.0) {
            // Parallel to the face: wholly inside or wholly outside.
            if (at < 0.0) {
                line.t_far = line.t_near;
            }
        } else if (along > 0.0) {
            line.t_near = glm::max(line.t_near, -at / along);
        } else {
            line.t_far = glm::min(line.t_far, -at / along);
        }
    }
    return line;
}

// Entry and exit of a ray from `origin` with the region as `user` sees it (as intersect_box: a
// ray starting inside gets t_near = 0; `hit` false when it misses).
[[nodiscard]] inline BoxHit intersect_region(const Region& region, glm::dvec3 origin,
                                             glm::dvec3 direction, RegionUser user) {
    const BoxHit box = intersect_box(origin, direction, region.box);
    if (!box.hit) {
        return box;
    }
    const LineInterval line = clip_to_half_spaces(region, region.count_for(user), origin, direction,
                                                  {box.t_near, box.t_far}, 0.0);
    return BoxHit{line.t_near, line.t_far, line.t_near < line.t_far};
}

// Whether `world` lies in the region as `user` sees it, faces included.
[[nodiscard]] inline bool contains(const Region& region, glm::dvec3 world, RegionUser user) {
    if (!region.box.contains(world)) {
        return false;
    }
    const int count = region.count_for(user);
    for (int i = 0; i < count; ++i) {
        const HalfSpace& h = region.half_spaces[static_cast<std::size_t>(i)];
        if (glm::dot(h.normal, world) + h.offset < 0.0) {
            return false;
        }
    }
    return true;
}

// The gradient at `world` (of value `value` there) with what the cut removed taken as empty, as
// vtk.js does, so that a face cut into tissue is shaded as a surface facing out of the cut, evenly,
// instead of by the material's inner gradient, which lies along the face and darkens it: within
// `reach` (a voxel) of a face camera rays clip by, the gradient's component along the face's
// normal becomes the central difference whose outer neighbour is empty, (v(p + reach n) - 0) /
// (2 reach), with v(p + reach n) taken as value + reach (gradient . n).
[[nodiscard]] inline glm::dvec3 gradient_at_cut(const Region& region, glm::dvec3 world,
                                                glm::dvec3 gradient, double value, double reach) {
    for (int i = 0; i < region.count; ++i) {
        const HalfSpace& h = region.half_spaces[static_cast<std::size_t>(i)];
        if (glm::dot(h.normal, world) + h.offset < reach) {
            const double along = glm::dot(gradient, h.normal);
            gradient += h.normal * ((value + reach * along) / (2.0 * reach) - along);
        }
    }
    return gradient;
}

}  // namespace penumbra::optics
