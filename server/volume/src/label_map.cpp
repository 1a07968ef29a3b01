#include "file_name.hpp"
#include "label_ids.hpp"

#include <penumbra/base/text.hpp>
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
    auto stored = load_volume(path, options);
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
