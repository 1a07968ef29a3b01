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

// Two rows of styles + 1 texels (index 0 the background, i the label styles[i - 1]). Row 0: rgb the
// label's colour, a how much of it replaces the transfer function's (the blend; 0 for the
// background). Row 1: r the opacity scale (the label's opacity, 0 when hidden; 1 for the
// background).
struct LabelStyleTable {
    int width = 0;
    std::vector<glm::vec4> texels;  // row 0, then row 1

    [[nodiscard]] glm::vec4 tint(int index) const {
        return texels[static_cast<std::size_t>(index)];
    }

    [[nodiscard]] float opacity_scale(int index) const {
        return texels[static_cast<std::size_t>(width + index)].r;
    }

    // Row 1 alone: all that the light sees of the labels (what a light buffer depends on).
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
    const glm::dvec4 tint(table.tint(index));
    const glm::dvec3 color = glm::dvec3(classified) * (1.0 - tint.a) + glm::dvec3(tint) * tint.a;
    return {color, classified.a * static_cast<double>(table.opacity_scale(index))};
}

}  // namespace penumbra::optics
