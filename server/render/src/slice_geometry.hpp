#pragma once

#include <penumbra/gpu/objects.hpp>
#include <penumbra/optics/region.hpp>

#include <glm/vec3.hpp>

#include <vector>

namespace penumbra::render {

// Triangles (a flat list of world positions) of every slice polygon, and where each slice's
// triangles start in that list: the geometry both slicers draw.
struct SliceGeometry {
    std::vector<float> positions;  // x, y, z per vertex
    std::vector<GLint> first;      // first vertex of slice k
    std::vector<GLsizei> count;    // vertex count of slice k (0 when the plane misses the box)
};

// The n slice polygons perpendicular to `normal` at min + (k + 0.5)·(max - min)/n, each cut to
// what `region` keeps for `user` and drawn as a triangle fan turned into a triangle list. A
// slice's fragments may read the slab up to its neighbours: along `normal` (`oblique_reach` 1),
// or, for a point light's rays, up to `oblique_reach` slice spacings in any direction (infinite:
// the slices are not cut); with `oblique_reach` 0 they read the slice plane alone, and the
// polygon is cut exactly.
SliceGeometry make_slice_geometry(const optics::Region& region, optics::RegionUser user,
                                  glm::dvec3 normal, double min, double max, int count,
                                  double oblique_reach = 1.0);

// How many slice spacings a point light's slab may reach from its slice plane: the slab runs
// along the light's ray, 1 / cos of the widest angle between a ray into `box` and the slicing
// axis `travel` (the rays to a box lie in the cone of those to its corners); infinite where that
// angle nears 90 degrees.
double point_light_reach(const scene::Box& box, glm::dvec3 position, glm::dvec3 travel);

// The geometry on the GPU: a vertex buffer and the vertex array reading it as attribute 0.
class SliceMesh {
public:
    SliceMesh();

    void upload(SliceGeometry geometry);

    // Draws slice k with `program`.
    void draw(const gpu::Program& program, int slice) const;

    [[nodiscard]] int slices() const { return static_cast<int>(geometry_.first.size()); }

private:
    gpu::Buffer buffer_;
    gpu::VertexArray vertex_array_;
    SliceGeometry geometry_;
    std::size_t capacity_ = 0;
};

}  // namespace penumbra::render
