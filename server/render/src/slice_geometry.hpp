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
// what `region` keeps for `user` and drawn as a triangle fan turned into a triangle list.
SliceGeometry make_slice_geometry(const optics::Region& region, optics::RegionUser user,
                                  glm::dvec3 normal, double min, double max, int count);

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
