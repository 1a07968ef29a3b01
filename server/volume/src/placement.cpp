// Where a loaded volume lies: its geometry as the file gives it, or, for a sheared transform, its
// voxels resampled onto an orthogonal grid (place_volume in volume.hpp).

#include "memory_budget.hpp"

#include <penumbra/volume/volume.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

namespace penumbra::volume {
namespace {

// A transform whose steps span less than this share of the box their lengths make is taken as
// degenerate: its voxels would spread over a sliver (a shear of more than about 89.9 degrees).
constexpr double min_volume_share = 1e-3;

// The most voxels the orthogonal grid may hold, as a multiple of the stored ones: a tilt of a few
// tens of degrees adds a fraction; more comes only of a shear near 90 degrees.
constexpr double max_grid_growth = 8.0;

// The grid a sheared volume is resampled onto (place_volume).
struct OrthogonalGrid {
    glm::dmat3 axes{1.0};  // columns: i's direction, j's made perpendicular to it, their normal
    glm::dvec3 spacing{1.0};
    glm::dvec3 first{0.0};  // the first voxel's centre, relative to the stored origin
    // Voxels per axis, as reals: a hostile transform's may exceed any integer type, and is
    // refused (place_volume) before it becomes one.
    glm::dvec3 sizes{0.0};

    [[nodiscard]] glm::uvec3 dims() const { return glm::uvec3(sizes); }
};

OrthogonalGrid grid_holding(const glm::dmat3& steps, glm::uvec3 stored) {
    OrthogonalGrid grid;
    const glm::dvec3 u = glm::normalize(steps[0]);
    const glm::dvec3 v = glm::normalize(steps[1] - glm::dot(steps[1], u) * u);
    glm::dvec3 w = glm::cross(u, v);
    if (glm::dot(w, steps[2]) < 0.0) {
        w = -w;  // a reflected transform stays reflected, as the file has it
    }
    grid.axes = glm::dmat3(u, v, w);
    grid.spacing = glm::dvec3(glm::length(steps[0]), std::abs(glm::dot(steps[1], v)),
                              std::abs(glm::dot(steps[2], w)));
    glm::dvec3 low(std::numeric_limits<double>::infinity());
    glm::dvec3 high(-std::numeric_limits<double>::infinity());
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 index((corner & 1) != 0 ? stored.x - 1.0 : 0.0,
                               (corner & 2) != 0 ? stored.y - 1.0 : 0.0,
                               (corner & 4) != 0 ? stored.z - 1.0 : 0.0);
        const glm::dvec3 in_grid = glm::transpose(grid.axes) * (steps * index);
        low = glm::min(low, in_grid);
        high = glm::max(high, in_grid);
    }
    grid.first = grid.axes * low;
    for (int a = 0; a < 3; ++a) {
        // Far enough to hold every stored centre; where they lie whole steps from the first (the
        // slices of a tilt), a hair's tolerance keeps rounding from adding a plane.
        grid.sizes[a] = std::ceil((high[a] - low[a]) / grid.spacing[a] - 1e-6) + 1.0;
    }
    return grid;
}

// Trilinear samples of `in` (stored values, x fastest) at the grid's voxel centres; `outside`
// where a centre lies beyond the stored ones by more than a hair.
template <class T>
void resample(std::span<const std::byte> in_bytes, glm::uvec3 in_dims, const glm::dmat3& steps,
              const OrthogonalGrid& grid, double outside, std::span<std::byte> out_bytes) {
    const auto* in = reinterpret_cast<const T*>(in_bytes.data());
    auto* out = reinterpret_cast<T*>(out_bytes.data());
    const glm::dmat3 to_index = glm::inverse(steps);
    const glm::dvec3 start = to_index * grid.first;
    const glm::dvec3 along_x = to_index * (grid.axes[0] * grid.spacing.x);
    const glm::dvec3 along_y = to_index * (grid.axes[1] * grid.spacing.y);
    const glm::dvec3 along_z = to_index * (grid.axes[2] * grid.spacing.z);
    const glm::dvec3 last = glm::dvec3(in_dims) - 1.0;
    constexpr double hair = 1e-6;
    const std::size_t row = in_dims.x;
    const std::size_t slice = row * in_dims.y;
    const auto store = [](double value) {
        if constexpr (std::is_integral_v<T>) {
            return static_cast<T>(std::clamp(std::round(value),
                                             double(std::numeric_limits<T>::lowest()),
                                             double(std::numeric_limits<T>::max())));
        } else {
            return static_cast<T>(value);
        }
    };
    const T fill = store(outside);
    const glm::uvec3 dims = grid.dims();
    std::size_t o = 0;
    for (std::uint32_t z = 0; z < dims.z; ++z) {
        for (std::uint32_t y = 0; y < dims.y; ++y) {
            glm::dvec3 index = start + along_z * double(z) + along_y * double(y);
            for (std::uint32_t x = 0; x < dims.x; ++x, ++o, index += along_x) {
                if (glm::any(glm::lessThan(index, glm::dvec3(-hair))) ||
                    glm::any(glm::greaterThan(index, last + hair))) {
                    out[o] = fill;
                    continue;
                }
                const glm::dvec3 at = glm::clamp(index, glm::dvec3(0.0), last);
                const glm::uvec3 low = glm::min(glm::uvec3(at), glm::max(in_dims, 2u) - 2u);
                const glm::dvec3 t = glm::clamp(at - glm::dvec3(low), 0.0, 1.0);
                const glm::uvec3 high = glm::min(low + 1u, in_dims - 1u);
                const auto value = [&](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
                    return static_cast<double>(in[k * slice + j * row + i]);
                };
                const auto lerp = [](double a, double b, double s) { return a + (b - a) * s; };
                const double front = lerp(
                        lerp(value(low.x, low.y, low.z), value(high.x, low.y, low.z), t.x),
                        lerp(value(low.x, high.y, low.z), value(high.x, high.y, low.z), t.x), t.y);
                const double back =
                        lerp(lerp(value(low.x, low.y, high.z), value(high.x, low.y, high.z), t.x),
                             lerp(value(low.x, high.y, high.z), value(high.x, high.y, high.z), t.x),
                             t.y);
                out[o] = store(lerp(front, back, t.z));
            }
        }
    }
}

// How far the most sheared pair of the steps is from perpendicular, in degrees, and which pair.
std::string shear_text(const glm::dmat3& steps) {
    static constexpr std::array<char, 3> names{'i', 'j', 'k'};
    double worst = -1.0;
    std::string text;
    for (int a = 0; a < 3; ++a) {
        for (int b = a + 1; b < 3; ++b) {
            const double cosine = glm::dot(glm::normalize(steps[a]), glm::normalize(steps[b]));
            const double angle =
                    std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / std::numbers::pi;
            if (std::abs(angle - 90.0) > worst) {
                worst = std::abs(angle - 90.0);
                char line[96];
                std::snprintf(line, sizeof line, "index axes %c and %c %.3g degrees apart",
                              names[static_cast<std::size_t>(a)],
                              names[static_cast<std::size_t>(b)], angle);
                text = line;
            }
        }
    }
    return text;
}

}  // namespace

base::Result<Geometry> placed_geometry(const glm::dmat3& steps, glm::dvec3 origin) {
    auto geometry = geometry_from_steps(steps, origin);
    if (geometry || geometry.error().code != base::ErrorCode::sheared_transform) {
        return geometry;
    }
    if (!std::isfinite(origin.x + origin.y + origin.z)) {
        return base::make_error(base::ErrorCode::bad_transform,
                                "the origin of the index-to-patient transform is not finite", "");
    }
    const double box = glm::length(steps[0]) * glm::length(steps[1]) * glm::length(steps[2]);
    if (!(std::abs(glm::determinant(steps)) > min_volume_share * box)) {
        base::Error error = geometry.error();
        error.message += ", and so nearly coplanar that its voxels span almost no volume";
        return error;
    }
    Geometry sheared;
    for (int column = 0; column < 3; ++column) {
        sheared.spacing[column] = glm::length(steps[column]);
        sheared.axes[column] = steps[column] / sheared.spacing[column];
    }
    sheared.origin = origin;
    sheared.sheared_steps = steps;
    return sheared;
}

base::Status place_volume(Volume& volume, const Geometry& geometry, const LoadOptions& options) {
    if (!geometry.note.empty()) {
        volume.notes.push_back(geometry.note);
    }
    if (!geometry.sheared_steps) {
        volume.spacing = geometry.spacing;
        volume.axes = geometry.axes;
        volume.origin = geometry.origin;
        return base::Ok{};
    }
    const glm::dmat3& steps = *geometry.sheared_steps;
    if (!options.resample_sheared) {
        return base::make_error(base::ErrorCode::sheared_transform,
                                "the " + shear_text(steps) +
                                        " (a gantry tilt or a shear); a label map is drawn on "
                                        "its own grid and cannot be resampled, which would mix "
                                        "its ids",
                                "");
    }
    const OrthogonalGrid grid = grid_holding(steps, volume.dims);
    const double voxels = grid.sizes.x * grid.sizes.y * grid.sizes.z;
    const double bytes = voxels * double(bytes_per_voxel(volume.type));
    char size[96];
    std::snprintf(size, sizeof size, "%.0fx%.0fx%.0f", grid.sizes.x, grid.sizes.y, grid.sizes.z);
    constexpr double max_side = double(std::numeric_limits<std::int32_t>::max());
    if (!(voxels <= max_grid_growth * double(volume.voxel_count())) ||
        !glm::all(glm::lessThanEqual(grid.sizes, glm::dvec3(max_side)))) {
        return base::make_error(
                base::ErrorCode::out_of_memory,
                "the sheared volume (" + shear_text(steps) + ") would need an orthogonal grid of " +
                        size + " voxels to hold it, more than " +
                        std::to_string(int(max_grid_growth)) + " times the voxels it stores",
                "");
    }
    // The stored voxels stay while the grid is filled.
    if (auto status = detail::check_budget(
                static_cast<std::uint64_t>(bytes) + volume.data.size(),
                std::string(size) + " voxels resampled from a sheared grid", volume.name, options);
        !status) {
        return status;
    }
    std::vector<std::byte> data;
    try {
        data.resize(static_cast<std::size_t>(bytes));
    } catch (const std::bad_alloc&) {
        return base::make_error(base::ErrorCode::out_of_memory,
                                "not enough memory to resample the sheared volume", "");
    }
    const double lowest_stored =
            (volume.range.min - volume.rescale.intercept) / volume.rescale.slope;
    switch (volume.type) {
        case VoxelType::uint8:
            resample<std::uint8_t>(volume.data, volume.dims, steps, grid, lowest_stored, data);
            break;
        case VoxelType::uint16:
            resample<std::uint16_t>(volume.data, volume.dims, steps, grid, lowest_stored, data);
            break;
        case VoxelType::int16:
            resample<std::int16_t>(volume.data, volume.dims, steps, grid, lowest_stored, data);
            break;
        case VoxelType::float32:
            resample<float>(volume.data, volume.dims, steps, grid, lowest_stored, data);
            break;
    }
    char line[256];
    std::snprintf(line, sizeof line,
                  "%s (a gantry tilt or a shear): resampled onto an orthogonal grid of %s "
                  "voxels (trilinear), as 3D Slicer and dcm2niix do",
                  shear_text(steps).c_str(), size);
    volume.notes.emplace_back(line);
    volume.data = std::move(data);
    volume.dims = grid.dims();
    volume.spacing = grid.spacing;
    volume.axes = grid.axes;
    volume.origin = geometry.origin + grid.first;
    return base::Ok{};
}

}  // namespace penumbra::volume
