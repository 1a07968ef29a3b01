#include <penumbra/optics/light_slicing.hpp>
#include <penumbra/optics/region.hpp>

#include <glm/matrix.hpp>

#include <algorithm>

namespace penumbra::optics {

Region region_of(const scene::Box& box, const scene::Cut& cut,
                 const scene::PatientPlacement& placement) {
    Region region;
    region.box = box;
    // A half-space that holds the whole box cuts nothing (a crop face at or beyond the volume's
    // bounds, a plane beside it): left out, it costs no test per sample, and a cut that removes
    // nothing is the uncut region, whose light buffer it shares. A face at the bounds that came
    // back through JSON may lie a rounding error inside them: a billionth of the box counts as on.
    constexpr double on_the_box = 1e-9;
    const auto corners = box_corners(box);
    const auto add = [&](glm::dvec3 normal, double offset) {
        const bool cuts = std::any_of(corners.begin(), corners.end(), [&](glm::dvec3 corner) {
            return glm::dot(normal, corner) + offset < -on_the_box;
        });
        if (cuts) {
            region.half_spaces[static_cast<std::size_t>(region.count++)] = {normal, offset};
        }
    };
    if (cut.crop.enabled) {
        // World space is patient space moved and scaled, never turned: the crop box's faces stay
        // perpendicular to the world axes.
        const glm::dvec3 low = placement.to_world(cut.crop.min);
        const glm::dvec3 high = placement.to_world(cut.crop.max);
        for (int axis = 0; axis < 3; ++axis) {
            glm::dvec3 normal(0.0);
            normal[axis] = 1.0;
            add(normal, -low[axis]);
            add(-normal, high[axis]);
        }
    }
    for (const scene::ClipPlane& plane : cut.planes) {
        if (plane.enabled) {
            // No rotation between the two spaces: a plane's normal is the same in both.
            const glm::dvec3 normal = glm::normalize(plane.normal);
            add(normal, -glm::dot(normal, placement.to_world(plane.point)));
        }
    }
    region.light_count = cut.casts_shadows ? 0 : region.count;
    return region;
}

bool outside_region(const Region& region, glm::dvec3 low, glm::dvec3 high, RegionUser user) {
    const int count = region.count_for(user);
    for (int i = 0; i < count; ++i) {
        const HalfSpace& h = region.half_spaces[static_cast<std::size_t>(i)];
        // dot(n, axes p) = dot(axes^T n, p): the normal in box space, and the part's corner
        // farthest along it, the last to leave the half-space.
        const glm::dvec3 normal = glm::transpose(region.box.axes) * h.normal;
        const glm::dvec3 farthest(normal.x >= 0.0 ? high.x : low.x,
                                  normal.y >= 0.0 ? high.y : low.y,
                                  normal.z >= 0.0 ? high.z : low.z);
        if (glm::dot(normal, farthest) + h.offset < 0.0) {
            return true;
        }
    }
    return false;
}

std::vector<glm::dvec3> clip_polygon(const Region& region, RegionUser user,
                                     std::vector<glm::dvec3> polygon) {
    const int count = region.count_for(user);
    std::vector<glm::dvec3> kept;
    for (int i = 0; i < count && polygon.size() >= 3; ++i) {
        // Sutherland-Hodgman: walk the edges, keep the vertices inside and add a vertex where an
        // edge crosses the half-space's plane.
        const HalfSpace& h = region.half_spaces[static_cast<std::size_t>(i)];
        const auto inside = [&](const glm::dvec3& p) { return glm::dot(h.normal, p) + h.offset; };
        kept.clear();
        for (std::size_t k = 0; k < polygon.size(); ++k) {
            const glm::dvec3& a = polygon[k];
            const glm::dvec3& b = polygon[(k + 1) % polygon.size()];
            const double da = inside(a);
            const double db = inside(b);
            if (da >= 0.0) {
                kept.push_back(a);
            }
            if ((da < 0.0) != (db < 0.0)) {
                kept.push_back(a + (b - a) * (da / (da - db)));
            }
        }
        polygon.swap(kept);
    }
    if (polygon.size() < 3) {
        polygon.clear();
    }
    return polygon;
}

}  // namespace penumbra::optics
