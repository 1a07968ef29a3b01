#pragma once

// How a frame draws the label map set beside its volume (a segmentation, an atlas): per label a
// colour, an opacity and a visibility. The label map itself (its voxels, ids and names) is the
// renderer's to hold (render::Renderer::set_labels); this is what a user changes frame to frame.

#include <penumbra/base/result.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace penumbra::scene {

struct LabelStyle {
    std::int64_t id = 0;    // the value the label map's voxels store
    glm::dvec3 color{1.0};  // RGB in [0, 1]
    double opacity = 1.0;   // scales what the scan's transfer function gives, 0..1
    bool visible = true;    // hidden: transparent to camera rays and to the light alike

    bool operator==(const LabelStyle&) const = default;
};

// At most this many labels are styled (volume::max_labels, the most a label map may hold).
inline constexpr std::size_t kMaxStyledLabels = 4096;

struct Labels {
    // One per label of the label map, in its order (the map's index i is styles[i - 1]; index 0,
    // the background, is drawn as the scan alone). Empty: no label map is drawn.
    std::vector<LabelStyle> styles;
    // How much a label's colour replaces the transfer function's: 0 the scan's colours, 1 the
    // label's alone (its opacity stays the scan's).
    double blend = 0.6;
    // The label map drawn alone, without the scan: each visible label a smooth lit surface in its
    // colour (labels_alone_request, volume::label_surfaces), the transfer function and the blend
    // set aside meanwhile.
    bool alone = false;

    [[nodiscard]] bool shown() const { return !styles.empty(); }

    bool operator==(const Labels&) const = default;
};

// Colours and opacities within [0, 1], at most kMaxStyledLabels styles, each id once.
base::Status validate(const Labels& labels);

// Whether each label is visible, in the map's order: what its surfaces are made of when the map
// is drawn alone (volume::label_surfaces).
[[nodiscard]] std::vector<bool> visibility(const Labels& labels);

// The transfer function that draws a label map alone as surfaces (volume::label_surfaces'
// indicator, whose values read as 0..1): transparent below 0.2, opaque from 0.35, so the surface
// lies where the indicator passes about 0.3, about half a voxel outside a flat face of a label
// (the filter's 11/16, 5/16 and 1/16 across it); white, for the labels' colours to replace whole
// (blend 1). A sheet of a label one voxel thin still shows (its indicator reaches 6/16).
TransferFunction label_surface_transfer_function();

// Whether `labels` styles exactly the labels `ids` lists, in its order (a label map's ids): what
// a frame drawn with that map must give, since a style is found by its label's index. An
// invalid_frame error says where they part.
base::Status check_styles_match(const Labels& labels, std::span<const std::int64_t> ids);

}  // namespace penumbra::scene
