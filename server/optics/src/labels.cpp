#include <penumbra/optics/labels.hpp>

#include <glm/matrix.hpp>

namespace penumbra::optics {

std::vector<float> LabelStyleTable::opacity_scales() const {
    std::vector<float> scales;
    for (const glm::vec4& texel : texels) {
        scales.push_back(texel.a);
    }
    return scales;
}

glm::dmat4 world_to_label_index(const scene::PatientPlacement& scan, glm::dvec3 origin,
                                const glm::dmat3& axes, glm::dvec3 spacing) {
    // index = (axes^T (patient - origin)) / spacing, patient = centre + world * mm_per_unit.
    glm::dmat3 linear = glm::transpose(axes) * scan.millimetres_per_unit;
    glm::dvec3 offset = glm::transpose(axes) * (scan.centre - origin);
    for (int row = 0; row < 3; ++row) {
        for (int column = 0; column < 3; ++column) {
            linear[column][row] /= spacing[row];
        }
        offset[row] /= spacing[row];
    }
    glm::dmat4 m(linear);
    m[3] = glm::dvec4(offset, 1.0);
    return m;
}

LabelStyleTable bake_label_styles(const scene::Labels& labels) {
    LabelStyleTable table;
    table.blend = static_cast<float>(labels.blend);
    table.texels.reserve(labels.styles.size() + 1);
    table.texels.emplace_back(1.0f);  // the background: the scan as it is
    for (const scene::LabelStyle& style : labels.styles) {
        table.texels.emplace_back(glm::vec3(style.color),
                                  style.visible ? static_cast<float>(style.opacity) : 0.0f);
    }
    return table;
}

}  // namespace penumbra::optics
