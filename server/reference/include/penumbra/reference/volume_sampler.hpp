#pragma once

#include <penumbra/optics/labels.hpp>
#include <penumbra/scene/box.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/scene/transfer_function.hpp>
#include <penumbra/volume/label_map.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <optional>
#include <vector>

namespace penumbra::reference {

// Samples a volume in world space as the GPU does (GL_LINEAR, GL_CLAMP_TO_EDGE, texel centres at
// (i + 0.5) / N), in double precision, with values mapped so the range is [0, 1]. The tricubic
// B-spline is summed over its 64 voxels directly (indices clamped to the edge), what the GPU's 8
// linear fetches add up to.
class VolumeSampler {
public:
    // How the sampler reads the voxels: `copied` maps every voxel to [0, 1] once (a whole image's
    // rays read each many times); `in_place` maps each voxel as it is read from `volume`, which
    // then outlives the sampler (one ray, as a pick follows, reads a few thousand of a volume that
    // can hold hundreds of millions).
    enum class Reading { copied, in_place };

    explicit VolumeSampler(const volume::Volume& volume,
                           scene::Reconstruction reconstruction = scene::Reconstruction::trilinear,
                           Reading reading = Reading::copied);

    [[nodiscard]] const scene::Box& box() const { return box_; }

    // One voxel's size along the box axes (box space), in world units.
    [[nodiscard]] glm::dvec3 voxel_size() const { return voxel_size_; }

    [[nodiscard]] double value(glm::dvec3 world) const;

    // In normalised value per world unit, in world space: trilinear, central differences one
    // voxel apart along the volume's axes; tricubic, the B-spline's derivative.
    [[nodiscard]] glm::dvec3 gradient(glm::dvec3 world) const;

private:
    [[nodiscard]] double normalized_voxel(int x, int y, int z) const;
    [[nodiscard]] double trilinear(glm::dvec3 world) const;
    // The B-spline along the box axes, `derivative_axis` (0..2) taking the derivative's weights
    // (per voxel step), -1 none.
    [[nodiscard]] double bspline(glm::dvec3 world, int derivative_axis) const;

    scene::Reconstruction reconstruction_;

    const volume::Volume* in_place_ = nullptr;  // read in place: the volume, else null
    double min_ = 0.0;                          // the range's minimum and width, for in_place_
    double width_ = 0.0;
    glm::ivec3 dims_;
    scene::Box box_;
    glm::dvec3 voxel_size_;
    std::vector<double> normalized_;  // copied: every voxel mapped to [0, 1] once
};

// The label of a world point of `scan` (as the renderer places it): the index of the label map's
// voxel nearest to it in the map's own grid, 0 outside it (shaders/include/labels.glsl); and a
// classified sample in that label under `styles`.
class LabelLookup {
public:
    LabelLookup(const volume::LabelMap& labels, const volume::Volume& scan,
                const scene::Labels& styles);

    [[nodiscard]] int index_at(glm::dvec3 world) const;

    // The label map's label of index `index` (1..); null for 0, the background.
    [[nodiscard]] const volume::Label* label(int index) const;

    [[nodiscard]] glm::dvec4 classify(glm::dvec4 classified, glm::dvec3 world) const;

private:
    const volume::LabelMap& labels_;
    glm::dmat4 world_to_index_;
    optics::LabelStyleTable styles_;
};

// The lookup a frame that styles labels draws with: none where it styles none; an invalid_frame
// error where no label map is given or the styles are not its labels in its order (as the
// renderer refuses such a frame).
base::Result<std::optional<LabelLookup>> lookup_labels(const volume::LabelMap* labels,
                                                       const volume::Volume& scan,
                                                       const scene::Labels& styles);

// A baked TF table read like the GPU's linearly filtered, edge-clamped 1D texture.
class TransferFunctionTable {
public:
    TransferFunctionTable(const scene::TransferFunction& tf, const scene::ValueDomain& values);

    [[nodiscard]] glm::dvec4 classify(double normalized_value) const;

    [[nodiscard]] const std::vector<glm::vec4>& entries() const { return table_; }

private:
    std::vector<glm::vec4> table_;
};

// Pre-integrated classification (optics/preintegration.hpp) in double: the segment from `front`
// to `back` as one sample of its average colour and equivalent TF opacity, from the integral of
// the table's (depth * colour, depth) at the entries' centres, by Simpson's rule over 32 parts
// between two entries as shaders/preintegration_table.comp does, but exact at any value rather
// than filtered from a table of them.
class SegmentClassifier {
public:
    SegmentClassifier(const TransferFunctionTable& tf, bool extinction);

    [[nodiscard]] glm::dvec4 classify(double front, double back) const;

private:
    [[nodiscard]] glm::dvec4 integrand(glm::dvec4 entry) const;
    [[nodiscard]] glm::dvec4 integral_from_entry(int k, double to) const;
    [[nodiscard]] glm::dvec4 cumulative_at(double value) const;

    const TransferFunctionTable& tf_;
    bool extinction_;
    std::vector<glm::dvec4> cumulative_;  // from 0 to entry k's centre
};

}  // namespace penumbra::reference
