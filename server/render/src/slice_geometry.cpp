#include "slice_geometry.hpp"

#include <penumbra/gpu/commands.hpp>
#include <penumbra/optics/light_slicing.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

namespace penumbra::render {

SliceGeometry make_slice_geometry(const optics::Region& region, optics::RegionUser user,
                                  glm::dvec3 normal, double min, double max, int count,
                                  double oblique_reach) {
    SliceGeometry geometry;
    geometry.first.reserve(static_cast<std::size_t>(count));
    geometry.count.reserve(static_cast<std::size_t>(count));
    const double spacing = (max - min) / count;
    const auto push = [&](const glm::dvec3& p) {
        geometry.positions.push_back(static_cast<float>(p.x));
        geometry.positions.push_back(static_cast<float>(p.y));
        geometry.positions.push_back(static_cast<float>(p.z));
    };
    // A slice's fragments march or blend the slab up to its neighbour: the polygon keeps every
    // point whose slab may reach into the region, so clipping drops only fragments that would
    // have added nothing.
    optics::Region reach = region;
    for (optics::HalfSpace& h : reach.half_spaces) {
        h.offset += oblique_reach == 0.0  ? 0.0
                    : oblique_reach > 1.0 ? spacing * oblique_reach
                                          : spacing * std::abs(glm::dot(h.normal, normal));
    }
    for (int k = 0; k < count; ++k) {
        const auto polygon = optics::clip_polygon(
                reach, user, optics::slice_polygon(region.box, normal, min + (k + 0.5) * spacing));
        geometry.first.push_back(static_cast<GLint>(geometry.positions.size() / 3));
        for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
            push(polygon[0]);
            push(polygon[i]);
            push(polygon[i + 1]);
        }
        geometry.count.push_back(static_cast<GLsizei>(geometry.positions.size() / 3) -
                                 geometry.first.back());
    }
    return geometry;
}

double point_light_reach(const scene::Box& box, glm::dvec3 position, glm::dvec3 travel) {
    double widest = 1.0;  // the least cosine
    for (const glm::dvec3& corner : optics::box_corners(box)) {
        widest = std::min(widest, glm::dot(glm::normalize(corner - position), travel));
    }
    return widest > 0.05 ? 1.0 / widest : std::numeric_limits<double>::infinity();
}

SliceMesh::SliceMesh()
    : vertex_array_(gpu::create_vertex_array()) {}

void SliceMesh::upload(SliceGeometry geometry) {
    geometry_ = std::move(geometry);
    const std::size_t bytes = std::max<std::size_t>(geometry_.positions.size() * sizeof(float), 16);
    if (!buffer_ || bytes > capacity_) {
        buffer_ = gpu::create_storage_buffer(bytes);
        capacity_ = bytes;
        gpu::attach_positions(vertex_array_, buffer_, 3);
    }
    if (!geometry_.positions.empty()) {
        gpu::upload(buffer_, std::as_bytes(std::span(geometry_.positions)));
    }
}

void SliceMesh::draw(const gpu::Program& program, int slice) const {
    const auto k = static_cast<std::size_t>(slice);
    if (geometry_.count[k] > 0) {
        gpu::draw_triangles(program, vertex_array_, geometry_.first[k], geometry_.count[k]);
    }
}

}  // namespace penumbra::render
