#include "label_ids.hpp"

#include <penumbra/volume/label_map.hpp>

#include <glm/common.hpp>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <map>

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
    std::map<std::int64_t, std::uint16_t> index_of{{0, 0}};
    for (const auto& [id, voxels] : *counts) {
        if (id == 0) {
            continue;
        }
        const auto found = named.find(id);
        map.labels.push_back(found != named.end()
                                     ? *found->second
                                     : Label{id, "label " + std::to_string(id), label_color(id)});
        map.voxels.push_back(voxels);
        index_of.emplace(id, static_cast<std::uint16_t>(map.labels.size()));
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
    indices->label_intent = true;
    map.indices = std::move(indices.value());
    return map;
}

base::Result<LabelMap> load_label_map(const std::filesystem::path& path,
                                      const LoadOptions& options) {
    auto stored = load_volume(path, options);
    if (!stored) {
        return stored.error();
    }
    LabelNames names;
    if (const auto files = find_mricron_labels(path)) {
        auto read = read_mricron_labels(*files);
        if (!read) {
            return read.error();
        }
        names = std::move(read.value());
    }
    return make_label_map(*stored, names);
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
