#pragma once

#include <penumbra/scene/box.hpp>
#include <penumbra/scene/transfer_function.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <vector>

namespace penumbra::reference {

// Samples a volume in world space exactly as the GPU does (GL_LINEAR, GL_CLAMP_TO_EDGE, texel
// centres at (i + 0.5) / N), in double precision, with values mapped so the range is [0, 1].
class VolumeSampler {
public:
    explicit VolumeSampler(const volume::Volume& volume);

    [[nodiscard]] const scene::Box& box() const { return box_; }

    // One voxel's size along the box axes (box space), in world units.
    [[nodiscard]] glm::dvec3 voxel_size() const { return voxel_size_; }

    [[nodiscard]] double value(glm::dvec3 world) const;

    // Central differences one voxel apart along the volume's axes, in normalised value per world
    // unit, turned into world space.
    [[nodiscard]] glm::dvec3 gradient(glm::dvec3 world) const;

private:
    [[nodiscard]] double normalized_voxel(int x, int y, int z) const;

    glm::ivec3 dims_;
    scene::Box box_;
    glm::dvec3 voxel_size_;
    std::vector<double> normalized_;  // every voxel mapped to [0, 1] once
};

// A baked TF table read like the GPU's linearly filtered, edge-clamped 1D texture.
class TransferFunctionTable {
public:
    TransferFunctionTable(const scene::TransferFunction& tf, const scene::ValueDomain& values);

    [[nodiscard]] glm::dvec4 classify(double normalized_value) const;

private:
    std::vector<glm::vec4> table_;
};

}  // namespace penumbra::reference
