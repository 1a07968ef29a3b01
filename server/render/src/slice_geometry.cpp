#include "slice_geometry.hpp"

#include <penumbra/optics/light_slicing.hpp>

#include <algorithm>

namespace penumbra::render {

SliceGeometry make_slice_geometry(const scene::Box& box, glm::dvec3 normal, double min, double max,
                                  int count) {
    SliceGeometry geometry;
    geometry.first.reserve(static_cast<std::size_t>(count));
    geometry.count.reserve(static_cast<std::size_t>(count));
    const double spacing = (max - min) / count;
    const auto push = [&](const glm::dvec3& p) {
        geometry.positions.push_back(static_cast<float>(p.x));
        geometry.positions.push_back(static_cast<float>(p.y));
        geometry.positions.push_back(static_cast<float>(p.z));
    };
    for (int k = 0; k < count; ++k) {
        const auto polygon = optics::slice_polygon(box, normal, min + (k + 0.5) * spacing);
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

SliceMesh::SliceMesh()
    : vertex_array_(gpu::create_vertex_array()) {}

void SliceMesh::upload(SliceGeometry geometry) {
    geometry_ = std::move(geometry);
    const std::size_t bytes = std::max<std::size_t>(geometry_.positions.size() * sizeof(float), 16);
    if (!buffer_ || bytes > capacity_) {
        buffer_ = gpu::create_buffer();
        glNamedBufferStorage(buffer_.name(), static_cast<GLsizeiptr>(bytes), nullptr,
                             GL_DYNAMIC_STORAGE_BIT);
        capacity_ = bytes;
        glVertexArrayVertexBuffer(vertex_array_.name(), 0, buffer_.name(), 0, 3 * sizeof(float));
        glVertexArrayAttribFormat(vertex_array_.name(), 0, 3, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(vertex_array_.name(), 0, 0);
        glEnableVertexArrayAttrib(vertex_array_.name(), 0);
    }
    if (!geometry_.positions.empty()) {
        glNamedBufferSubData(buffer_.name(), 0,
                             static_cast<GLsizeiptr>(geometry_.positions.size() * sizeof(float)),
                             geometry_.positions.data());
    }
}

void SliceMesh::bind() const {
    glBindVertexArray(vertex_array_.name());
}

void SliceMesh::draw(int slice) const {
    const auto k = static_cast<std::size_t>(slice);
    if (geometry_.count[k] > 0) {
        glDrawArrays(GL_TRIANGLES, geometry_.first[k], geometry_.count[k]);
    }
}

}  // namespace penumbra::render
