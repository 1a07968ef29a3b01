#include "label_ids.hpp"

#include <penumbra/volume/label_names.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>

namespace penumbra::volume {
namespace {

constexpr std::size_t lut_entries = 256;
constexpr std::uintmax_t lut_bytes = 3 * lut_entries;

}  // namespace

std::optional<MricronLabelFiles> find_mricron_labels(const std::filesystem::path& volume_path) {
    std::string stem = volume_path.string();
    if (stem.size() > 3 && stem.ends_with(".gz")) {
        stem.resize(stem.size() - 3);
    }
    if (!stem.ends_with(".nii")) {
        return std::nullopt;
    }
    std::error_code error;
    const std::filesystem::path names = stem + ".txt";
    if (!std::filesystem::is_regular_file(names, error)) {
        return std::nullopt;
    }
    MricronLabelFiles files{names, std::nullopt};
    if (const std::filesystem::path colors = stem + ".lut";
        std::filesystem::is_regular_file(colors, error)) {
        files.colors = colors;
    }
    return files;
}

glm::u8vec3 label_color(std::int64_t id) {
    const double hue = std::fmod(static_cast<double>(id) * 0.6180339887498949, 1.0) * 6.0;
    const double saturation = 0.65;
    const double value = 0.9;
    const double fraction = hue - std::floor(hue);
    const double p = value * (1.0 - saturation);
    const double q = value * (1.0 - saturation * fraction);
    const double t = value * (1.0 - saturation * (1.0 - fraction));
    const std::array<glm::dvec3, 6> sectors{glm::dvec3(value, t, p), glm::dvec3(q, value, p),
                                            glm::dvec3(p, value, t), glm::dvec3(p, q, value),
                                            glm::dvec3(t, p, value), glm::dvec3(value, p, q)};
    const glm::dvec3 rgb = sectors[static_cast<std::size_t>(std::floor(hue)) % 6];
    return glm::u8vec3(glm::round(rgb * 255.0));
}

base::Result<LabelNames> read_mricron_labels(const MricronLabelFiles& files) {
    std::ifstream names(files.names);
    if (!names) {
        return base::make_error(base::ErrorCode::io_error, "cannot read the label names",
                                files.names.string());
    }
    std::vector<std::byte> lut;
    if (files.colors) {
        std::error_code error;
        const std::uintmax_t size = std::filesystem::file_size(*files.colors, error);
        if (error || size != lut_bytes) {
            return base::make_error(
                    base::ErrorCode::bad_data,
                    "a label colour table (.lut) must hold 768 bytes (256 reds, greens and blues); "
                    "this one holds " +
                            (error ? std::string("none that can be read") : std::to_string(size)),
                    files.colors->string());
        }
        std::ifstream in(*files.colors, std::ios::binary);
        lut.resize(lut_bytes);
        if (!in.read(reinterpret_cast<char*>(lut.data()),
                     static_cast<std::streamsize>(lut_bytes))) {
            return base::make_error(base::ErrorCode::io_error, "cannot read the label colours",
                                    files.colors->string());
        }
    }
    LabelNames result;
    std::string line;
    int number = 0;
    while (std::getline(names, line)) {
        ++number;
        if (!line.empty() && line.back() == '\r') {
            line.pop_back();
        }
        if (line.find_first_not_of(" \t") == std::string::npos) {
            continue;
        }
        std::istringstream fields(line);
        Label label;
        if (!(fields >> label.id >> label.name)) {
            result.warnings.push_back(files.names.filename().string() + " line " +
                                      std::to_string(number) +
                                      ": not `id name`, skipped: " + line.substr(0, 80));
            continue;
        }
        if (!lut.empty() && label.id >= 0 && static_cast<std::size_t>(label.id) < lut_entries) {
            const auto entry = static_cast<std::size_t>(label.id);
            label.color = {std::to_integer<std::uint8_t>(lut[entry]),
                           std::to_integer<std::uint8_t>(lut[lut_entries + entry]),
                           std::to_integer<std::uint8_t>(lut[2 * lut_entries + entry])};
        } else {
            label.color = label_color(label.id);
        }
        result.labels.push_back(std::move(label));
    }
    return result;
}

std::int64_t label_id_of_voxel(const Volume& volume, std::size_t index) {
    const std::size_t size = bytes_per_voxel(volume.type);
    const std::byte* voxel = volume.data.data() + index * size;
    std::int64_t stored = 0;
    switch (volume.type) {
        case VoxelType::uint8:
            stored = std::to_integer<std::uint8_t>(voxel[0]);
            break;
        case VoxelType::uint16:
        case VoxelType::int16: {
            const auto bits = static_cast<std::uint16_t>(std::to_integer<unsigned>(voxel[0]) |
                                                         std::to_integer<unsigned>(voxel[1]) << 8U);
            stored = volume.type == VoxelType::int16 ? static_cast<std::int16_t>(bits) : bits;
            break;
        }
        case VoxelType::float32:
            PENUMBRA_ASSERT(false, "a label map's voxels are integers");
    }
    return std::llround(volume.rescale.apply(static_cast<double>(stored)));
}

base::Result<std::map<std::int64_t, std::uint64_t>> count_labels(const Volume& volume) {
    if (volume.type == VoxelType::float32) {
        return base::make_error(base::ErrorCode::invalid_volume,
                                "a label map holds integer ids; this volume holds floating-point "
                                "values",
                                volume.name);
    }
    std::map<std::int64_t, std::uint64_t> counts;
    for (std::size_t i = 0; i < volume.voxel_count(); ++i) {
        auto [entry, added] = counts.try_emplace(label_id_of_voxel(volume, i), 0);
        ++entry->second;
        if (added && counts.size() > max_labels) {
            return base::make_error(base::ErrorCode::too_large,
                                    "a label map may hold at most " + std::to_string(max_labels) +
                                            " labels; this one holds more",
                                    volume.name);
        }
    }
    return counts;
}

std::string describe_labels(const LabelNames& names,
                            const std::map<std::int64_t, std::uint64_t>& counts) {
    std::map<std::int64_t, Label> table;
    for (const Label& label : names.labels) {
        table.try_emplace(label.id, label);
    }
    for (const auto& [id, voxels] : counts) {
        if (id != 0 && !table.contains(id)) {
            table.emplace(id, Label{id, "label " + std::to_string(id), label_color(id)});
        }
    }
    std::string out = "labels:      " + std::to_string(table.size()) + "\n";
    for (const auto& [id, label] : table) {
        const auto found = counts.find(id);
        char row[64];
        std::snprintf(row, sizeof row, "  %6lld  #%02x%02x%02x  %10llu  ",
                      static_cast<long long>(id), label.color.r, label.color.g, label.color.b,
                      static_cast<unsigned long long>(found == counts.end() ? 0 : found->second));
        out += row + label.name + "\n";
    }
    for (const std::string& warning : names.warnings) {
        out += "warning:     " + warning + "\n";
    }
    return out;
}

}  // namespace penumbra::volume
