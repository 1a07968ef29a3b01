#include "penumbra/reference/volume_sampler.hpp"

#include <glm/common.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace penumbra::reference {
namespace {

// Texel index and weight along one axis for texture coordinate `t` (GL_LINEAR, clamp to edge).
struct AxisSample {
    int i0;
    int i1;
    double f;
};

AxisSample axis_sample(double t, int n) {
    const double c = t * n - 0.5;
    const double floor_c = std::floor(c);
    const int i = static_cast<int>(floor_c);
    return {std::clamp(i, 0, n - 1), std::clamp(i + 1, 0, n - 1), c - floor_c};
}

// The cubic B-spline's weights of voxels i-1..i+2 at fraction `f` past voxel i, and its
// derivative's (per voxel step).
std::array<double, 4> bspline_weights(double f) {
    const double g = 1.0 - f;
    return {g * g * g / 6.0, (3.0 * f * f * f - 6.0 * f * f + 4.0) / 6.0,
            (-3.0 * f * f * f + 3.0 * f * f + 3.0 * f + 1.0) / 6.0, f * f * f / 6.0};
}

std::array<double, 4> bspline_derivative_weights(double f) {
    const double g = 1.0 - f;
    return {-0.5 * g * g, 0.5 * f * (3.0 * f - 4.0), 0.5 * (1.0 + 3.0 * f) * g, 0.5 * f * f};
}

}  // namespace

VolumeSampler::VolumeSampler(const volume::Volume& volume, scene::Reconstruction reconstruction)
    : reconstruction_(reconstruction)
    , dims_(glm::ivec3(volume.dims))
    , box_(scene::box_for_extent(volume.extent(), volume.axes))
    , voxel_size_(box_.size() / glm::dvec3(volume.dims))
    , normalized_(volume.voxel_count()) {
    const double width = volume.range.max - volume.range.min;
    std::size_t i = 0;
    for (std::uint32_t z = 0; z < volume.dims.z; ++z) {
        for (std::uint32_t y = 0; y < volume.dims.y; ++y) {
            for (std::uint32_t x = 0; x < volume.dims.x; ++x) {
                normalized_[i++] =
                        width > 0.0 ? (volume.value(x, y, z) - volume.range.min) / width : 0.0;
            }
        }
    }
}

double VolumeSampler::normalized_voxel(int x, int y, int z) const {
    return normalized_[(static_cast<std::size_t>(z) * dims_.y + y) * dims_.x + x];
}

double VolumeSampler::value(glm::dvec3 world) const {
    switch (reconstruction_) {
        case scene::Reconstruction::trilinear:
            return trilinear(world);
        case scene::Reconstruction::tricubic:
            return bspline(world, -1);
    }
    return trilinear(world);
}

double VolumeSampler::trilinear(glm::dvec3 world) const {
    const glm::dvec3 t = (box_.to_box(world) - box_.min) / box_.size();
    const AxisSample sx = axis_sample(t.x, dims_.x);
    const AxisSample sy = axis_sample(t.y, dims_.y);
    const AxisSample sz = axis_sample(t.z, dims_.z);
    const auto along_x = [&](int y, int z) {
        return glm::mix(normalized_voxel(sx.i0, y, z), normalized_voxel(sx.i1, y, z), sx.f);
    };
    const double z0 = glm::mix(along_x(sy.i0, sz.i0), along_x(sy.i1, sz.i0), sy.f);
    const double z1 = glm::mix(along_x(sy.i0, sz.i1), along_x(sy.i1, sz.i1), sy.f);
    return glm::mix(z0, z1, sz.f);
}

double VolumeSampler::bspline(glm::dvec3 world, int derivative_axis) const {
    const glm::dvec3 t = (box_.to_box(world) - box_.min) / box_.size();
    std::array<std::array<double, 4>, 3> weights{};
    std::array<std::array<int, 4>, 3> indices{};
    for (int axis = 0; axis < 3; ++axis) {
        const double x = t[axis] * dims_[axis] - 0.5;
        const double below = std::floor(x);
        weights[axis] = axis == derivative_axis ? bspline_derivative_weights(x - below)
                                                : bspline_weights(x - below);
        for (int k = 0; k < 4; ++k) {
            indices[axis][k] = std::clamp(static_cast<int>(below) - 1 + k, 0, dims_[axis] - 1);
        }
    }
    double sum = 0.0;
    for (int z = 0; z < 4; ++z) {
        for (int y = 0; y < 4; ++y) {
            for (int x = 0; x < 4; ++x) {
                sum += weights[0][x] * weights[1][y] * weights[2][z] *
                       normalized_voxel(indices[0][x], indices[1][y], indices[2][z]);
            }
        }
    }
    return sum;
}

glm::dvec3 VolumeSampler::gradient(glm::dvec3 world) const {
    if (reconstruction_ == scene::Reconstruction::tricubic) {
        const glm::dvec3 per_step(bspline(world, 0), bspline(world, 1), bspline(world, 2));
        return box_.to_world(per_step / voxel_size_);
    }
    const glm::dvec3 h = voxel_size_;
    const glm::dvec3 dx = h.x * box_.axes[0];
    const glm::dvec3 dy = h.y * box_.axes[1];
    const glm::dvec3 dz = h.z * box_.axes[2];
    const glm::dvec3 along_axes(value(world + dx) - value(world - dx),
                                value(world + dy) - value(world - dy),
                                value(world + dz) - value(world - dz));
    // The axes are orthonormal, so the box-space gradient turns into world space like a vector.
    return box_.to_world(along_axes / (2.0 * h));
}

TransferFunctionTable::TransferFunctionTable(const scene::TransferFunction& tf,
                                             const scene::ValueDomain& values)
    : table_(scene::bake(tf, scene::default_table_size, values)) {}

glm::dvec4 TransferFunctionTable::classify(double normalized_value) const {
    const AxisSample s =
            axis_sample(std::clamp(normalized_value, 0.0, 1.0), static_cast<int>(table_.size()));
    return glm::mix(glm::dvec4(table_[s.i0]), glm::dvec4(table_[s.i1]), s.f);
}

}  // namespace penumbra::reference
