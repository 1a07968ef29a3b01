#pragma once

// What a label does to a classified sample, written once for the renderer's style table and the
// CPU reference and mirrored by shaders/include/labels.glsl: the transfer function gives the
// opacity, the label scales it (0 where hidden) and tints the colour by its own.

#include <penumbra/scene/box.hpp>
#include <penumbra/scene/labels.hpp>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <vector>

namespace penumbra::optics {

// One texel per label and one for the background before them (index 0; i is the label
// styles[i - 1]): rgb the label's colour, a its opacity scale (its opacity, 0 when hidden; 1 for
// the background). A label's colour replaces `blend` of the transfer function's; the background's
// none.
struct LabelStyleTable {
    std::vector<glm::vec4> texels;
    float blend = 0.0f;

    // The opacity scales alone: all that the light sees of the labels (what a light buffer
    // depends on).
    [[nodiscard]] std::vector<float> opacity_scales() const;
};

// From the world space of a scan placed by `scan` to the voxel index space of a label map (voxel
// i's centre at i) whose voxel (0, 0, 0) is centred at patient point `origin`, its index axes along
// the orthonormal columns of `axes`, `spacing` apart: the map keeps its own grid, and a sample's
// label is the voxel nearest to it there.
[[nodiscard]] glm::dmat4 world_to_label_index(const scene::PatientPlacement& scan,
                                              glm::dvec3 origin, const glm::dmat3& axes,
                                              glm::dvec3 spacing);

[[nodiscard]] LabelStyleTable bake_label_styles(const scene::Labels& labels);

// The sample the transfer function classified as `classified`, in the label of index `index`.
[[nodiscard]] inline glm::dvec4 classify_in_label(glm::dvec4 classified,
                                                  const LabelStyleTable& table, int index) {
    const glm::dvec4 style(table.texels[static_cast<std::size_t>(index)]);
    const double weight = index == 0 ? 0.0 : static_cast<double>(table.blend);
    const glm::dvec3 color = glm::dvec3(classified) * (1.0 - weight) + glm::dvec3(style) * weight;
    return {color, classified.a * style.a};
}

}  // namespace penumbra::optics
