#include "label_ids.hpp"

#include <penumbra/volume/label_names.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>

namespace penumbra::volume {
namespace {

constexpr std::size_t lut_entries = 256;
constexpr std::uintmax_t lut_bytes = 3 * lut_entries;

// Calls `on_line(number, line)` for each line of `in` that holds more than blanks, without its
// CR (names files come from Windows too), numbered from 1.
template <class OnLine>
void for_each_line(std::istream& in, const OnLine& on_line) {
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
        ++number;
        if (!line.empty() && line.back() == '\r') {
            line.pop_back();
        }
        if (line.find_first_not_of(" \t") != std::string::npos) {
            on_line(number, line);
        }
    }
}

std::string line_warning(const std::filesystem::path& path, int number, const std::string& line,
                         const char* expected) {
    return path.filename().string() + " line " + std::to_string(number) + ": not " + expected +
           ", skipped: " + line.substr(0, 80);
}

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
    double turn = std::fmod(static_cast<double>(id) * 0.6180339887498949, 1.0);
    if (turn < 0.0) {
        turn += 1.0;  // negative ids (int16 maps, Slicer's label values) turn the other way round
    }
    const double hue = std::min(turn * 6.0, 5.999999);
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
    for_each_line(names, [&](int number, const std::string& line) {
        std::istringstream fields(line);
        Label label;
        if (!(fields >> label.id >> label.name)) {
            result.warnings.push_back(line_warning(files.names, number, line, "`id name`"));
            return;
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
    });
    return result;
}

namespace {

std::uint8_t colour_component(double value) {
    return static_cast<std::uint8_t>(std::clamp(value, 0.0, 255.0));
}

// ITK-SNAP: IDX R G B A VIS MSH "LABEL".
std::optional<Label> itk_snap_label(const std::string& line) {
    const std::size_t open = line.find('"');
    const std::size_t close = line.rfind('"');
    if (open == std::string::npos || close <= open) {
        return std::nullopt;
    }
    std::istringstream fields(line.substr(0, open));
    Label label;
    double r = 0.0;
    double g = 0.0;
    double b = 0.0;
    double alpha = 1.0;
    int visible = 1;
    int mesh = 1;
    if (!(fields >> label.id >> r >> g >> b >> alpha >> visible >> mesh)) {
        return std::nullopt;
    }
    label.name = line.substr(open + 1, close - open - 1);
    label.color = {colour_component(r), colour_component(g), colour_component(b)};
    label.opacity = std::clamp(alpha, 0.0, 1.0);
    label.visible = visible != 0;
    return label;
}

// FreeSurfer: id name R G B A, A the transparency (0 opaque).
std::optional<Label> freesurfer_label(const std::string& line) {
    std::istringstream fields(line);
    Label label;
    int r = 0;
    int g = 0;
    int b = 0;
    int transparency = 0;
    if (!(fields >> label.id >> label.name >> r >> g >> b >> transparency)) {
        return std::nullopt;
    }
    label.color = {colour_component(r), colour_component(g), colour_component(b)};
    label.opacity = 1.0 - std::clamp(transparency, 0, 255) / 255.0;
    return label;
}

}  // namespace

base::Result<LabelNames> read_label_description(const std::filesystem::path& path) {
    std::ifstream file(path);
    if (!file) {
        return base::make_error(base::ErrorCode::io_error, "cannot read the label description",
                                path.string());
    }
    LabelNames result;
    for_each_line(file, [&](int number, const std::string& line) {
        if (line[line.find_first_not_of(" \t")] == '#') {
            return;
        }
        auto label =
                line.find('"') != std::string::npos ? itk_snap_label(line) : freesurfer_label(line);
        if (!label) {
            result.warnings.push_back(line_warning(path, number, line,
                                                   "ITK-SNAP's `IDX R G B A VIS MSH \"LABEL\"` or "
                                                   "FreeSurfer's `id name R G B A`"));
            return;
        }
        result.labels.push_back(std::move(*label));
    });
    return result;
}

base::Result<LabelNames> read_slicer_segments(const NrrdKeyValues& keys) {
    // SegmentN_Field, by N.
    std::map<int, std::map<std::string, std::string>> segments;
    for (const auto& [key, value] : keys) {
        if (!key.starts_with("Segment")) {
            continue;
        }
        const std::size_t underscore = key.find('_');
        const std::string number =
                key.substr(7, underscore == std::string::npos ? std::string::npos : underscore - 7);
        if (underscore == std::string::npos || number.empty() || number.size() > 6 ||
            (number.size() > 1 && number.front() == '0') ||
            number.find_first_not_of("0123456789") != std::string::npos) {
            continue;  // "Segmentation_..." keys describe the whole file
        }
        segments[std::stoi(number)][key.substr(underscore + 1)] = value;
    }
    LabelNames result;
    for (const auto& segment : segments) {
        const int number = segment.first;
        const std::map<std::string, std::string>& fields = segment.second;
        const auto field = [&](const char* name) -> std::optional<std::string> {
            const auto found = fields.find(name);
            return found == fields.end() ? std::nullopt : std::optional(found->second);
        };
        const auto whole_number = [](const std::string& text) -> std::optional<std::int64_t> {
            std::int64_t value = 0;
            const auto [end, error] =
                    std::from_chars(text.data(), text.data() + text.size(), value);
            if (error != std::errc{} || end != text.data() + text.size()) {
                return std::nullopt;
            }
            return value;
        };
        const auto layer_text = field("Layer");
        const auto layer = layer_text ? whole_number(*layer_text) : std::optional<std::int64_t>(0);
        if (!layer) {
            result.warnings.push_back("Segment" + std::to_string(number) +
                                      "_Layer is not a whole number, read as 0: " + *layer_text);
        } else if (*layer != 0) {
            return base::make_error(base::ErrorCode::unsupported_dimension,
                                    "segment " + std::to_string(number) + " lies on layer " +
                                            *layer_text +
                                            ": its segments overlap, which a label map cannot "
                                            "hold; in 3D Slicer, export them to a labelmap first",
                                    "Segment" + std::to_string(number) + "_Layer");
        }
        Label label;
        label.id = number + 1;
        if (const auto value = field("LabelValue")) {
            const auto parsed = whole_number(*value);
            if (parsed) {
                label.id = *parsed;
            } else {
                result.warnings.push_back("Segment" + std::to_string(number) +
                                          "_LabelValue is not a whole number: " + *value);
                continue;
            }
        }
        label.name = field("Name").value_or("Segment_" + std::to_string(number + 1));
        label.color = label_color(label.id);
        if (const auto color = field("Color")) {
            std::istringstream in(*color);
            double r = 0.0;
            double g = 0.0;
            double b = 0.0;
            if (in >> r >> g >> b) {
                label.color = {colour_component(std::round(r * 255.0)),
                               colour_component(std::round(g * 255.0)),
                               colour_component(std::round(b * 255.0))};
            } else {
                result.warnings.push_back("Segment" + std::to_string(number) +
                                          "_Color is not three numbers: " + *color);
            }
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

}  // namespace penumbra::volume
