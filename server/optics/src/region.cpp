#include <penumbra/optics/region.hpp>

namespace penumbra::optics {

Region region_of(const scene::Box& box, const scene::Cut& cut,
                 const scene::PatientPlacement& placement) {
    Region region;
    region.box = box;
    if (cut.crop.enabled) {
        // World space is patient space moved and scaled, never turned: the crop box's faces stay
        // perpendicular to the world axes.
        const glm::dvec3 low = placement.to_world(cut.crop.min);
        const glm::dvec3 high = placement.to_world(cut.crop.max);
        for (int axis = 0; axis < 3; ++axis) {
            glm::dvec3 normal(0.0);
            normal[axis] = 1.0;
            region.half_spaces[static_cast<std::size_t>(region.count++)] = {normal, -low[axis]};
            region.half_spaces[static_cast<std::size_t>(region.count++)] = {-normal, high[axis]};
        }
    }
    for (const scene::ClipPlane& plane : cut.planes) {
        if (plane.enabled) {
            // No rotation between the two spaces: a plane's normal is the same in both.
            const glm::dvec3 normal = glm::normalize(plane.normal);
            region.half_spaces[static_cast<std::size_t>(region.count++)] = {
                    normal, -glm::dot(normal, placement.to_world(plane.point))};
        }
    }
    region.light_count = cut.casts_shadows ? 0 : region.count;
    return region;
}

}  // namespace penumbra::optics
