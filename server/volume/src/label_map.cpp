#include "file_name.hpp"
#include "label_ids.hpp"

#include <penumbra/base/text.hpp>
#include <penumbra/volume/label_map.hpp>

#include <glm/common.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <map>
#include <span>

namespace penumbra::volume {
namespace {

std::string describe_box(const PatientBounds& box) {
    char text[160];
    std::snprintf(text, sizeof text, "(%.1f, %.1f, %.1f)..(%.1f, %.1f, %.1f) mm", box.min.x,
                  box.min.y, box.min.z, box.max.x, box.max.y, box.max.z);
    return text;
}

}  // namespace

base::Result<LabelMap> make_label_map(const Volume& stored, const LabelNames& names) {
    if (stored.volumes_in_file > 1) {
        return base::make_error(base::ErrorCode::unsupported_dimension,
                                "a label map holds one volume of label ids; this file holds " +
                                        std::to_string(stored.volumes_in_file) +
                                        " (a probabilistic atlas or a time series?)",
                                stored.name);
    }
    auto counts = count_labels(stored);
    if (!counts) {
        return counts.error();
    }
    std::map<std::int64_t, const Label*> named;
    for (const Label& label : names.labels) {
        named.try_emplace(label.id, &label);
    }
    LabelMap map;
    map.warnings = names.warnings;
    map.named = !names.labels.empty();
    std::map<std::int64_t, std::uint16_t> index_of{{0, 0}};
    for (const auto& [id, voxels] : *counts) {
        if (id == 0) {
            map.background_voxels = voxels;
            continue;
        }
        const auto found = named.find(id);
        Label label = found != named.end()
                              ? *found->second
                              : Label{id, "label " + std::to_string(id), label_color(id)};
        // Names reach JSON messages: a Latin-1 atlas or a hostile file must not break one.
        label.name = base::valid_utf8(label.name, max_label_name_bytes);
        map.labels.push_back(std::move(label));
        map.voxels.push_back(voxels);
        index_of.emplace(id, static_cast<std::uint16_t>(map.labels.size()));
    }
    if (map.labels.empty()) {
        return base::make_error(base::ErrorCode::invalid_volume,
                                "a label map needs a label: every voxel of this one holds 0, the "
                                "background",
                                stored.name);
    }
    std::size_t absent = 0;
    for (const auto& [id, label] : named) {
        absent += id != 0 && !counts->contains(id) ? 1 : 0;
    }
    if (absent > 0) {
        map.warnings.push_back(std::to_string(absent) +
                               " named label(s) hold no voxel of the volume and are left out");
    }
    const bool narrow = map.labels.size() <= 255;
    const VoxelType type = narrow ? VoxelType::uint8 : VoxelType::uint16;
    std::vector<std::byte> data(stored.voxel_count() * bytes_per_voxel(type));
    // Neighbouring voxels mostly hold the same label: one lookup per run of them.
    std::int64_t run_id = 0;
    std::uint16_t index = 0;
    for (std::size_t i = 0; i < stored.voxel_count(); ++i) {
        if (const std::int64_t id = label_id_of_voxel(stored, i); id != run_id) {
            run_id = id;
            index = index_of.at(id);
        }
        if (narrow) {
            data[i] = static_cast<std::byte>(index);
        } else {
            std::memcpy(data.data() + 2 * i, &index, 2);  // little endian (volume.cpp asserts it)
        }
    }
    auto indices = make_volume(stored.name, stored.dims, stored.spacing, type, std::move(data));
    if (!indices) {
        return indices.error();
    }
    indices->axes = stored.axes;
    indices->origin = stored.origin;
    indices->label_intent = stored.label_intent;
    map.indices = std::move(indices.value());
    return map;
}

namespace {

bool is_nrrd_name(const std::filesystem::path& path) {
    const std::string name = detail::lower_file_name(path);
    return detail::has_suffix(name, ".nrrd") || detail::has_suffix(name, ".nhdr");
}

bool is_nifti_name(const std::filesystem::path& path) {
    const std::string name = detail::lower_file_name(path);
    return detail::has_suffix(name, ".nii") || detail::has_suffix(name, ".nii.gz") ||
           detail::has_suffix(name, ".hdr");
}

}  // namespace

base::Result<LabelNames> label_names_for(const std::filesystem::path& path,
                                         const std::filesystem::path& names) {
    if (!names.empty()) {
        return read_label_description(names);
    }
    if (const auto files = find_mricron_labels(path)) {
        return read_mricron_labels(*files);
    }
    if (is_nrrd_name(path)) {
        auto keys = read_nrrd_key_values(path);
        if (!keys) {
            return keys.error();
        }
        return read_slicer_segments(*keys);
    }
    return LabelNames{};
}

namespace {

// The index voxel i of a label map's indices holds, in the map's index type (`data` the indices'
// bytes, or a copy being changed).
std::uint16_t index_of_voxel(VoxelType type, std::span<const std::byte> data, std::size_t i) {
    if (type == VoxelType::uint8) {
        return std::to_integer<std::uint8_t>(data[i]);
    }
    std::uint16_t index = 0;
    std::memcpy(&index, data.data() + 2 * i, 2);
    return index;
}

// One pass of the 1 2 1 filter along the axis whose voxels lie `stride` apart and that holds
// `size` of them; outside the grid is background (0).
void binomial_pass(std::vector<std::uint16_t>& field, std::size_t stride, std::uint32_t size) {
    std::vector<std::uint16_t> out(field.size());
    for (std::size_t i = 0; i < field.size(); ++i) {
        const std::size_t along = i / stride % size;
        const std::uint32_t below = along > 0 ? field[i - stride] : 0;
        const std::uint32_t above = along + 1 < size ? field[i + stride] : 0;
        out[i] = static_cast<std::uint16_t>(below + 2U * field[i] + above);
    }
    field.swap(out);
}

}  // namespace

base::Result<LabelSurfaces> label_surfaces(const LabelMap& map, const std::vector<bool>& visible) {
    if (visible.size() != map.labels.size()) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "one visibility per label: " + std::to_string(visible.size()) +
                                        " for " + std::to_string(map.labels.size()) + " labels",
                                map.indices.name);
    }
    const Volume& indices = map.indices;
    const glm::uvec3 dims = indices.dims;
    const std::size_t count = indices.voxel_count();
    const auto shown = [&](std::uint16_t index) {
        return index > 0 && visible[static_cast<std::size_t>(index - 1)];
    };
    std::vector<std::uint16_t> field(count);
    for (std::size_t i = 0; i < count; ++i) {
        field[i] = shown(index_of_voxel(indices.type, indices.data, i)) ? 1 : 0;
    }
    const std::size_t slice = static_cast<std::size_t>(dims.x) * dims.y;
    // Twice along each axis: 1 4 6 4 1, a Gaussian of about a voxel, which smooths the steps of
    // a shallow slope (the 1 2 1 filter alone leaves them as terraces).
    for (int pass = 0; pass < 2; ++pass) {
        binomial_pass(field, 1, dims.x);
        binomial_pass(field, dims.x, dims.y);
        binomial_pass(field, slice, dims.z);
    }
    constexpr std::uint32_t full = 16 * 16 * 16;  // a voxel whose neighbourhood is all inside
    std::vector<std::byte> values(count);
    for (std::size_t i = 0; i < count; ++i) {
        values[i] = static_cast<std::byte>((field[i] * 255U + full / 2) / full);
    }

    // Voxels of no visible label that the surface may pass (within the filter's reach, two voxels;
    // the background, or a hidden label, which adds nothing to the indicator) take a visible
    // neighbour's index, ring by ring: the faces' first, then the edges', then the corners' (the
    // fewer axes an offset moves along, the nearer).
    std::vector<glm::ivec3> offsets;
    for (int moved = 1; moved <= 3; ++moved) {
        for (int z = -1; z <= 1; ++z) {
            for (int y = -1; y <= 1; ++y) {
                for (int x = -1; x <= 1; ++x) {
                    if ((x != 0) + (y != 0) + (z != 0) == moved) {
                        offsets.emplace_back(x, y, z);
                    }
                }
            }
        }
    }
    std::vector<std::byte> dilated = indices.data;
    std::vector<std::byte> before_ring;
    const bool wide = indices.type == VoxelType::uint16;
    const glm::ivec3 size(dims);
    for (int ring = 0; ring < 2; ++ring) {
        before_ring = dilated;
        for (std::size_t i = 0; i < count; ++i) {
            if (field[i] == 0 || shown(index_of_voxel(indices.type, before_ring, i))) {
                continue;
            }
            const glm::ivec3 voxel(static_cast<int>(i % dims.x),
                                   static_cast<int>(i / dims.x % dims.y),
                                   static_cast<int>(i / slice));
            for (const glm::ivec3 offset : offsets) {
                const glm::ivec3 n = voxel + offset;
                if (glm::any(glm::lessThan(n, glm::ivec3(0))) ||
                    glm::any(glm::greaterThanEqual(n, size))) {
                    continue;
                }
                const std::size_t j = static_cast<std::size_t>(n.x) + dims.x * n.y + slice * n.z;
                const std::uint16_t index = index_of_voxel(indices.type, before_ring, j);
                if (shown(index)) {
                    if (wide) {
                        std::memcpy(dilated.data() + 2 * i, &index, 2);
                    } else {
                        dilated[i] = static_cast<std::byte>(index);
                    }
                    break;
                }
            }
        }
    }

    auto indicator = make_volume(indices.name + " surfaces", dims, indices.spacing,
                                 VoxelType::uint8, std::move(values));
    if (!indicator) {
        return indicator.error();
    }
    indicator->axes = indices.axes;
    indicator->origin = indices.origin;
    indicator->range = {0.0, 255.0};
    auto coloured =
            make_volume(indices.name, dims, indices.spacing, indices.type, std::move(dilated));
    if (!coloured) {
        return coloured.error();
    }
    coloured->axes = indices.axes;
    coloured->origin = indices.origin;
    coloured->label_intent = indices.label_intent;
    LabelMap labels;
    labels.indices = std::move(coloured.value());
    labels.labels = map.labels;
    labels.voxels = map.voxels;
    labels.background_voxels = map.background_voxels;
    labels.named = map.named;
    labels.warnings = map.warnings;
    return LabelSurfaces{std::move(indicator.value()), std::move(labels)};
}

std::vector<std::int64_t> LabelMap::ids() const {
    std::vector<std::int64_t> out;
    out.reserve(labels.size());
    for (const Label& label : labels) {
        out.push_back(label.id);
    }
    return out;
}

base::Result<bool> declares_labels(const std::filesystem::path& path) {
    if (find_mricron_labels(path)) {
        return true;
    }
    if (is_nrrd_name(path)) {
        auto keys = read_nrrd_key_values(path);
        if (!keys) {
            return keys.error();
        }
        auto segments = read_slicer_segments(*keys);
        if (!segments) {
            return segments.error();
        }
        return !segments->labels.empty();
    }
    if (is_nifti_name(path)) {
        return read_nifti_label_intent(path);
    }
    return false;
}

std::string describe_labels(const LabelMap& labels) {
    std::string out = "labels:      " + std::to_string(labels.labels.size()) + "\n";
    for (std::size_t i = 0; i < labels.labels.size(); ++i) {
        const Label& label = labels.labels[i];
        char row[64];
        std::snprintf(row, sizeof row, "  %6lld  #%02x%02x%02x  %10llu  ",
                      static_cast<long long>(label.id), label.color.r, label.color.g, label.color.b,
                      static_cast<unsigned long long>(labels.voxels[i]));
        out += row + label.name + "\n";
    }
    out += "background:  " + std::to_string(labels.background_voxels) + " voxels\n";
    for (const std::string& warning : labels.warnings) {
        out += "warning:     " + warning + "\n";
    }
    return out;
}

base::Result<LabelMap> load_label_map(const std::filesystem::path& path, const LoadOptions& options,
                                      const std::filesystem::path& names) {
    std::error_code error;
    if (std::filesystem::is_directory(path, error) || is_dicom_file(path)) {
        return base::make_error(base::ErrorCode::unsupported_format,
                                "label maps from DICOM (DICOM SEG objects) are not supported; "
                                "save the segmentation as NIfTI or as 3D Slicer's .seg.nrrd",
                                path.filename().string());
    }
    // The names first: a .seg.nrrd whose segments overlap is refused for that, not for its
    // 4-D layout.
    auto named = label_names_for(path, names);
    if (!named) {
        return named.error();
    }
    LoadOptions exact = options;
    exact.resample_sheared = false;  // interpolation would mix the ids
    auto stored = load_volume(path, exact);
    if (!stored) {
        return stored.error();
    }
    return make_label_map(*stored, *named);
}

base::Status check_overlap(const Volume& scan, const Volume& labels) {
    const PatientBounds a = patient_bounds(scan);
    const PatientBounds b = patient_bounds(labels);
    const glm::dvec3 low = glm::max(a.min, b.min);
    const glm::dvec3 high = glm::min(a.max, b.max);
    if (low.x < high.x && low.y < high.y && low.z < high.z) {
        return base::Ok{};
    }
    return base::make_error(base::ErrorCode::no_overlap,
                            "the label map '" + labels.name + "' lies at " + describe_box(b) +
                                    ", outside the scan '" + scan.name + "' at " + describe_box(a) +
                                    ": they share no part of patient space",
                            labels.name);
}

}  // namespace penumbra::volume
