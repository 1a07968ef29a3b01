#include "empty_space.hpp"

#include <penumbra/base/assert.hpp>
#include <penumbra/gpu/commands.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <glm/common.hpp>
#include <glm/matrix.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace penumbra::render {
namespace {

// The voxel index range [first, last] that samples in brick `brick` can read along one axis of
// `voxels` voxels cut into `bricks`: a sample at texture coordinate t reads voxels floor(t * n -
// 0.5) and the one above. The small margin keeps rounding of t at a brick face on the safe side.
std::pair<unsigned, unsigned> voxels_read(int brick, int bricks, unsigned voxels) {
    constexpr double margin = 1e-3;
    const double per_brick = double(voxels) / bricks;
    const double first = std::floor(brick * per_brick - 0.5 - margin);
    const double last = std::floor((brick + 1) * per_brick - 0.5 + margin) + 1.0;
    const double top = double(voxels) - 1.0;
    return {static_cast<unsigned>(std::clamp(first, 0.0, top)),
            static_cast<unsigned>(std::clamp(last, 0.0, top))};
}

template <class T>
BrickRanges ranges_of(const volume::Volume& volume, int brick_voxels) {
    const glm::uvec3 dims = volume.dims;
    BrickRanges out;
    out.grid = (glm::ivec3(dims) + brick_voxels - 1) / brick_voxels;
    out.min_max.resize(static_cast<std::size_t>(out.grid.x) * out.grid.y * out.grid.z);
    const double width = volume.range.max - volume.range.min;
    const auto normalised = [&](double raw) {
        return width > 0.0 ? static_cast<float>((raw - volume.range.min) / width) : 0.0f;
    };
    std::vector<T> row(dims.x);
    std::size_t index = 0;
    for (int bz = 0; bz < out.grid.z; ++bz) {
        const auto [z0, z1] = voxels_read(bz, out.grid.z, dims.z);
        for (int by = 0; by < out.grid.y; ++by) {
            const auto [y0, y1] = voxels_read(by, out.grid.y, dims.y);
            for (int bx = 0; bx < out.grid.x; ++bx) {
                const auto [x0, x1] = voxels_read(bx, out.grid.x, dims.x);
                T lo = std::numeric_limits<T>::max();
                T hi = std::numeric_limits<T>::lowest();
                for (unsigned z = z0; z <= z1; ++z) {
                    for (unsigned y = y0; y <= y1; ++y) {
                        const std::size_t start = (std::size_t(z) * dims.y + y) * dims.x + x0;
                        const std::size_t count = x1 - x0 + 1;
                        std::memcpy(row.data(), volume.data.data() + start * sizeof(T),
                                    count * sizeof(T));
                        const auto [mn, mx] = std::minmax_element(row.begin(), row.begin() + count);
                        lo = std::min(lo, *mn);
                        hi = std::max(hi, *mx);
                    }
                }
                // Real values (the rescale applied), in the order a negative slope leaves them.
                const double a = volume.rescale.apply(double(lo));
                const double b = volume.rescale.apply(double(hi));
                out.min_max[index++] = {normalised(std::min(a, b)), normalised(std::max(a, b))};
            }
        }
    }
    return out;
}

// The label indices of `labels` (voxels of type T) nearest to any point of each brick of `grid`
// over `scan`.
template <class T>
BrickLabels labels_of(const volume::Volume& scan, glm::ivec3 grid, const volume::LabelMap& labels) {
    const volume::Volume& map = labels.indices;
    // Scan texture coordinate t -> patient (origin + axes ((t dims - 1/2) spacing)) -> the map's
    // continuous index (axes^T (patient - origin) / spacing), whose nearest voxel is
    // floor(index + 1/2).
    const glm::dvec3 scan_dims(scan.dims);
    const auto to_map_index = [&](glm::dvec3 t) {
        const glm::dvec3 patient = scan.origin + scan.axes * ((t * scan_dims - 0.5) * scan.spacing);
        return (glm::transpose(map.axes) * (patient - map.origin)) / map.spacing;
    };
    // A thousandth of a voxel on either side, as voxels_read allows, in both grids.
    constexpr double margin = 1e-3;
    const glm::dvec3 brick_size = 1.0 / glm::dvec3(grid);
    const glm::ivec3 map_dims(map.dims);
    const auto* voxels = reinterpret_cast<const T*>(map.data.data());
    std::vector<std::uint32_t> seen_in(labels.labels.size() + 1, 0);  // brick number + 1
    BrickLabels out;
    out.grid = grid;
    out.starts.reserve(static_cast<std::size_t>(grid.x) * grid.y * grid.z + 1);
    std::uint32_t brick_number = 0;
    for (int bz = 0; bz < grid.z; ++bz) {
        for (int by = 0; by < grid.y; ++by) {
            for (int bx = 0; bx < grid.x; ++bx) {
                ++brick_number;
                out.starts.push_back(static_cast<std::uint32_t>(out.indices.size()));
                const glm::dvec3 low = glm::dvec3(bx, by, bz) * brick_size - margin / scan_dims;
                const glm::dvec3 high = low + brick_size + 2.0 * margin / scan_dims;
                glm::dvec3 least(std::numeric_limits<double>::max());
                glm::dvec3 most(std::numeric_limits<double>::lowest());
                for (int corner = 0; corner < 8; ++corner) {
                    const glm::dvec3 t((corner & 1) != 0 ? high.x : low.x,
                                       (corner & 2) != 0 ? high.y : low.y,
                                       (corner & 4) != 0 ? high.z : low.z);
                    const glm::dvec3 index = to_map_index(t);
                    least = glm::min(least, index);
                    most = glm::max(most, index);
                }
                const glm::dvec3 first_voxel = glm::floor(least + 0.5 - margin);
                const glm::dvec3 last_voxel = glm::floor(most + 0.5 + margin);
                const auto mark = [&](std::uint32_t index) {
                    if (seen_in[index] != brick_number) {
                        seen_in[index] = brick_number;
                        out.indices.push_back(index);
                    }
                };
                if (glm::any(glm::lessThan(first_voxel, glm::dvec3(0.0))) ||
                    glm::any(glm::greaterThanEqual(last_voxel, glm::dvec3(map_dims)))) {
                    mark(0);  // some of the brick lies outside the map
                }
                if (glm::any(glm::greaterThan(first_voxel, glm::dvec3(map_dims - 1))) ||
                    glm::any(glm::lessThan(last_voxel, glm::dvec3(0.0)))) {
                    continue;  // the brick lies wholly outside the map: its one index is marked
                }
                const glm::ivec3 first(glm::max(first_voxel, glm::dvec3(0.0)));
                const glm::ivec3 last(glm::min(last_voxel, glm::dvec3(map_dims - 1)));
                for (int z = first.z; z <= last.z; ++z) {
                    for (int y = first.y; y <= last.y; ++y) {
                        const std::size_t row = (std::size_t(z) * map_dims.y + y) * map_dims.x;
                        for (int x = first.x; x <= last.x; ++x) {
                            mark(voxels[row + x]);
                        }
                    }
                }
                std::sort(out.indices.begin() + out.starts.back(), out.indices.end());
            }
        }
    }
    out.starts.push_back(static_cast<std::uint32_t>(out.indices.size()));
    return out;
}

}  // namespace

BrickLabels compute_brick_labels(const volume::Volume& scan, glm::ivec3 grid,
                                 const volume::LabelMap& labels) {
    if (labels.indices.type == volume::VoxelType::uint8) {
        return labels_of<std::uint8_t>(scan, grid, labels);
    }
    PENUMBRA_ASSERT(labels.indices.type == volume::VoxelType::uint16,
                    "label indices are 8 or 16 bits");
    return labels_of<std::uint16_t>(scan, grid, labels);
}

BrickRanges compute_brick_ranges(const volume::Volume& volume, int brick_voxels) {
    switch (volume.type) {
        case volume::VoxelType::uint8:
            return ranges_of<std::uint8_t>(volume, brick_voxels);
        case volume::VoxelType::uint16:
            return ranges_of<std::uint16_t>(volume, brick_voxels);
        case volume::VoxelType::int16:
            return ranges_of<std::int16_t>(volume, brick_voxels);
        case volume::VoxelType::float32:
            return ranges_of<float>(volume, brick_voxels);
    }
    return {};
}

scene::OccupiedBricks occupied_bricks(const BrickRanges& ranges,
                                      const std::vector<glm::vec4>& table,
                                      const optics::Region& region, const LabelVisibility& labels) {
    scene::OccupiedBricks occupied;
    occupied.first = ranges.grid;
    const int entries = static_cast<int>(table.size());
    std::vector<std::uint32_t> visible_before(table.size() + 1, 0);
    for (std::size_t i = 0; i < table.size(); ++i) {
        visible_before[i + 1] = visible_before[i] + (table[i].a > 0.0f ? 1u : 0u);
    }
    const auto visible_in_table = [&](glm::vec2 stored) {
        if (table.empty()) {
            return true;
        }
        // The shader's arithmetic, in float as there, so both count the same bricks.
        const glm::vec2 range = glm::clamp(stored, 0.0f, 1.0f);
        const int lowest = std::clamp(
                static_cast<int>(std::floor(range.x * float(entries) - 0.5f)) - 1, 0, entries - 1);
        const int highest = std::clamp(
                static_cast<int>(std::floor(range.y * float(entries) - 0.5f)) + 2, 0, entries - 1);
        return visible_before[static_cast<std::size_t>(highest) + 1] >
               visible_before[static_cast<std::size_t>(lowest)];
    };
    // Brick (i, j, k) covers [i, i + 1) / grid of the box along each axis.
    const glm::dvec3 brick_size = region.box.size() / glm::dvec3(ranges.grid);
    const bool cut = region.count_for(optics::RegionUser::light) > 0;
    const auto inside_region = [&](glm::ivec3 brick) {
        const glm::dvec3 low = region.box.min + glm::dvec3(brick) * brick_size;
        return !optics::outside_region(region, low, glm::min(low + brick_size, region.box.max),
                                       optics::RegionUser::light);
    };
    const auto any_label_shown = [&](std::size_t brick) {
        if (labels.bricks == nullptr) {
            return true;
        }
        const BrickLabels& bricks = *labels.bricks;
        for (std::uint32_t k = bricks.starts[brick]; k < bricks.starts[brick + 1]; ++k) {
            if (bricks.indices[k] < labels.shown.size() && labels.shown[bricks.indices[k]]) {
                return true;
            }
        }
        return false;
    };
    std::size_t index = 0;
    for (const glm::vec2& stored : ranges.min_max) {
        const glm::ivec3 brick(static_cast<int>(index % ranges.grid.x),
                               static_cast<int>(index / ranges.grid.x % ranges.grid.y),
                               static_cast<int>(index / ranges.grid.x / ranges.grid.y));
        ++index;
        if (visible_in_table(stored) && (!cut || inside_region(brick)) &&
            any_label_shown(index - 1)) {
            ++occupied.count;
            occupied.first = glm::min(occupied.first, brick);
            occupied.last = glm::max(occupied.last, brick);
        }
    }
    if (occupied.count == 0) {
        occupied.first = glm::ivec3(0);
    }
    return occupied;
}

EmptySpaceMap::EmptySpaceMap(const BrickRanges& ranges)
    : ranges_on_cpu_(ranges)
    , ranges_(gpu::create_texture_3d(GL_RG32F, ranges.grid.x, ranges.grid.y, ranges.grid.z))
    , occupancy_(gpu::create_texture_3d(GL_R16UI, ranges.grid.x, ranges.grid.y, ranges.grid.z))
    , visible_entries_(
              gpu::create_storage_buffer(sizeof(std::uint32_t) * (scene::default_table_size + 1))) {
    const glm::ivec3 grid = ranges.grid;
    gpu::upload_3d(ranges_, grid.x, grid.y, grid.z, GL_RG, GL_FLOAT, ranges.min_max.data());
    // Read with texelFetch; a filter without mipmaps keeps their single level complete.
    gpu::set_sampling(ranges_, GL_NEAREST, GL_CLAMP_TO_EDGE);
    gpu::set_sampling(occupancy_, GL_NEAREST, GL_CLAMP_TO_EDGE);
}

base::Status EmptySpaceMap::classify(ProgramCache& programs, bool labels) const {
    const glm::ivec3 grid = ranges_on_cpu_.grid;
    auto program = programs.compute("brick_classify.comp", {{"LABELS", labels ? "1" : "0"}});
    if (!program) {
        return program.error();
    }
    const gpu::Program& classify = **program;
    gpu::bind_storage_buffer(0, visible_entries_);
    gpu::bind_texture(4, ranges_);
    gpu::bind_image(0, occupancy_, GL_WRITE_ONLY, GL_R16UI);
    gpu::set_uniform(classify, 0, 0);  // the table's visible entries, into the buffer
    gpu::dispatch(classify, {}, GL_SHADER_STORAGE_BARRIER_BIT);
    gpu::set_uniform(classify, 0, 1);  // each brick against them
    gpu::dispatch(classify, gpu::groups_covering(4, grid.x, grid.y, grid.z),
                  GL_TEXTURE_FETCH_BARRIER_BIT);
    return base::Ok{};
}

}  // namespace penumbra::render
