#include "penumbra/reference/volume_sampler.hpp"

#include <penumbra/optics/preintegration.hpp>

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

VolumeSampler::VolumeSampler(const volume::Volume& volume, scene::Reconstruction reconstruction,
                             Reading reading)
    : reconstruction_(reconstruction)
    , min_(volume.range.min)
    , width_(volume.range.max - volume.range.min)
    , dims_(glm::ivec3(volume.dims))
    , box_(scene::box_for_extent(volume.extent(), volume.axes))
    , voxel_size_(box_.size() / glm::dvec3(volume.dims)) {
    switch (reading) {
        case Reading::in_place:
            in_place_ = &volume;
            return;
        case Reading::copied:
            break;
    }
    normalized_.resize(volume.voxel_count());
    std::size_t i = 0;
    for (std::uint32_t z = 0; z < volume.dims.z; ++z) {
        for (std::uint32_t y = 0; y < volume.dims.y; ++y) {
            for (std::uint32_t x = 0; x < volume.dims.x; ++x) {
                normalized_[i++] = width_ > 0.0 ? (volume.value(x, y, z) - min_) / width_ : 0.0;
            }
        }
    }
}

double VolumeSampler::normalized_voxel(int x, int y, int z) const {
    if (in_place_ != nullptr) {
        return width_ > 0.0 ? (in_place_->value(static_cast<std::uint32_t>(x),
                                                static_cast<std::uint32_t>(y),
                                                static_cast<std::uint32_t>(z)) -
                               min_) / width_
                            : 0.0;
    }
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

LabelLookup::LabelLookup(const volume::LabelMap& labels, const volume::Volume& scan,
                         const scene::Labels& styles)
    : labels_(labels)
    , world_to_index_(optics::world_to_label_index(
              scene::patient_placement(scan.origin, scan.axes, scan.spacing, glm::dvec3(scan.dims)),
              labels.indices.origin, labels.indices.axes, labels.indices.spacing))
    , styles_(optics::bake_label_styles(styles)) {}

base::Result<std::optional<LabelLookup>> lookup_labels(const volume::LabelMap* labels,
                                                       const volume::Volume& scan,
                                                       const scene::Labels& styles) {
    if (!styles.shown()) {
        return std::optional<LabelLookup>{};
    }
    if (labels == nullptr) {
        return base::make_error(base::ErrorCode::invalid_frame,
                                "the frame styles labels, but no label map is given", "labels");
    }
    if (auto status = scene::check_styles_match(styles, labels->ids()); !status) {
        return status.error();
    }
    return std::optional<LabelLookup>(std::in_place, *labels, scan, styles);
}

int LabelLookup::index_at(glm::dvec3 world) const {
    const glm::dvec3 index = glm::floor(glm::dvec3(world_to_index_ * glm::dvec4(world, 1.0)) + 0.5);
    const glm::dvec3 dims(labels_.indices.dims);
    if (index.x < 0.0 || index.y < 0.0 || index.z < 0.0 || index.x >= dims.x || index.y >= dims.y ||
        index.z >= dims.z) {
        return 0;
    }
    return static_cast<int>(labels_.indices.value(static_cast<std::uint32_t>(index.x),
                                                  static_cast<std::uint32_t>(index.y),
                                                  static_cast<std::uint32_t>(index.z)));
}

const volume::Label* LabelLookup::label(int index) const {
    return index > 0 ? &labels_.labels[static_cast<std::size_t>(index - 1)] : nullptr;
}

glm::dvec4 LabelLookup::classify(glm::dvec4 classified, glm::dvec3 world) const {
    if (classified.a <= 0.0) {
        return classified;
    }
    return optics::classify_in_label(classified, styles_, index_at(world));
}

TransferFunctionTable::TransferFunctionTable(const scene::TransferFunction& tf,
                                             const scene::ValueDomain& values)
    : table_(scene::bake(tf, scene::default_table_size, values)) {}

glm::dvec4 TransferFunctionTable::classify(double normalized_value) const {
    const AxisSample s =
            axis_sample(std::clamp(normalized_value, 0.0, 1.0), static_cast<int>(table_.size()));
    return glm::mix(glm::dvec4(table_[s.i0]), glm::dvec4(table_[s.i1]), s.f);
}

SegmentClassifier::SegmentClassifier(const TransferFunctionTable& tf, bool extinction)
    : tf_(tf)
    , extinction_(extinction) {
    const auto& entries = tf.entries();
    const int n = static_cast<int>(entries.size());
    glm::dvec4 sum = integrand(glm::dvec4(entries[0])) * (0.5 / n);
    for (int k = 0; k < n; ++k) {
        cumulative_.push_back(sum);
        if (k + 1 < n) {
            sum += integral_from_entry(k, 1.0);
        }
    }
}

glm::dvec4 SegmentClassifier::integrand(glm::dvec4 entry) const {
    const double depth = optics::optical_depth_of_opacity(entry.a, extinction_);
    return {depth * glm::dvec3(entry), depth};
}

glm::dvec4 SegmentClassifier::integral_from_entry(int k, double to) const {
    constexpr int parts = 32;
    const auto& entries = tf_.entries();
    const glm::dvec4 a(entries[k]);
    const glm::dvec4 b(entries[k + 1]);
    const double h = to / parts;
    glm::dvec4 sum = integrand(a) + integrand(glm::mix(a, b, to));
    for (int p = 1; p < parts; ++p) {
        sum += double(2 + 2 * (p & 1)) * integrand(glm::mix(a, b, p * h));
    }
    return sum * (h / 3.0) / double(entries.size());
}

glm::dvec4 SegmentClassifier::cumulative_at(double value) const {
    const auto& entries = tf_.entries();
    const int n = static_cast<int>(entries.size());
    const double x = value * n - 0.5;
    if (x <= 0.0) {
        return integrand(glm::dvec4(entries[0])) * value;
    }
    if (x >= n - 1) {
        return cumulative_[n - 1] + integrand(glm::dvec4(entries[n - 1])) * ((x - (n - 1)) / n);
    }
    const int k = static_cast<int>(std::floor(x));
    return cumulative_[k] + integral_from_entry(k, x - k);
}

glm::dvec4 SegmentClassifier::classify(double front, double back) const {
    front = std::clamp(front, 0.0, 1.0);
    back = std::clamp(back, 0.0, 1.0);
    const glm::dvec4 middle = tf_.classify(0.5 * (front + back));
    const double weight = optics::table_weight(front, back);
    if (weight == 0.0) {
        return middle;
    }
    const glm::dvec4 integral = cumulative_at(back) - cumulative_at(front);
    const double depth = std::max(integral.a / (back - front), 0.0);
    const glm::dvec3 colour = depth > 1e-6 ? glm::clamp(glm::dvec3(integral) / integral.a, 0.0, 1.0)
                                           : glm::dvec3(middle);
    const glm::dvec4 mixed = glm::mix(
            glm::dvec4(glm::dvec3(middle), optics::optical_depth_of_opacity(middle.a, extinction_)),
            glm::dvec4(colour, depth), weight);
    return {glm::dvec3(mixed), optics::opacity_of_optical_depth(mixed.a, extinction_)};
}

}  // namespace penumbra::reference
