#include "file_io.hpp"
#include "file_name.hpp"

#include <penumbra/volume/volume.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <string_view>

namespace penumbra::volume {

// Volume::data is little endian by contract and the loaders copy file bytes straight into it.
static_assert(std::endian::native == std::endian::little,
              "Penumbra's volume layout assumes a little-endian host");

namespace {

template <class T>
T load_sample(const std::vector<std::byte>& data, std::size_t index) {
    T sample;
    std::memcpy(&sample, data.data() + index * sizeof(T), sizeof(T));
    return sample;
}

base::Error invalid(std::string message, const std::string& name) {
    return base::make_error(base::ErrorCode::invalid_volume, std::move(message), name);
}

// Replaces NaN and ±Inf by the smallest finite value (0 when there is none) so that the GPU and
// the histogram never see them; returns how many were replaced and the finite range.
std::uint64_t sanitise_float32(std::vector<std::byte>& data, ValueRange& range) {
    const std::size_t count = data.size() / sizeof(float);
    float lo = std::numeric_limits<float>::infinity();
    float hi = -std::numeric_limits<float>::infinity();
    std::uint64_t nonfinite = 0;
    for (std::size_t i = 0; i < count; ++i) {
        const float v = load_sample<float>(data, i);
        if (std::isfinite(v)) {
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        } else {
            ++nonfinite;
        }
    }
    if (nonfinite == count) {
        lo = 0.0f;
        hi = 0.0f;
    }
    if (nonfinite > 0) {
        for (std::size_t i = 0; i < count; ++i) {
            if (!std::isfinite(load_sample<float>(data, i))) {
                std::memcpy(data.data() + i * sizeof(float), &lo, sizeof(float));
            }
        }
    }
    range = {static_cast<double>(lo), static_cast<double>(hi)};
    return nonfinite;
}

template <class T>
ValueRange integer_range(const std::vector<std::byte>& data, const Rescale& rescale) {
    const std::size_t count = data.size() / sizeof(T);
    T lo = std::numeric_limits<T>::max();
    T hi = std::numeric_limits<T>::lowest();
    for (std::size_t i = 0; i < count; ++i) {
        const T v = load_sample<T>(data, i);
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
    const double a = rescale.apply(static_cast<double>(lo));
    const double b = rescale.apply(static_cast<double>(hi));
    return {std::min(a, b), std::max(a, b)};
}

std::size_t bin_index(double value, const Histogram& histogram) {
    const double width = histogram.range.max - histogram.range.min;
    if (!(width > 0.0)) {
        return 0;
    }
    const double position = (value - histogram.range.min) / width;
    const double last = static_cast<double>(histogram.bins.size() - 1);
    const double bin = std::floor(position * static_cast<double>(histogram.bins.size()));
    return static_cast<std::size_t>(std::clamp(bin, 0.0, last));
}

// Counts each of the 2^bits possible integer values once, then spreads the counts over the bins
// by their real values: far cheaper than a division per voxel for 8- and 16-bit volumes.
template <class T>
void histogram_of_integers(const Volume& volume, Histogram& histogram) {
    constexpr auto lowest = static_cast<std::int64_t>(std::numeric_limits<T>::lowest());
    std::vector<std::uint64_t> counts(std::size_t{1} << (8 * sizeof(T)), 0);
    const std::size_t count = volume.voxel_count();
    for (std::size_t i = 0; i < count; ++i) {
        ++counts[static_cast<std::size_t>(load_sample<T>(volume.data, i) - lowest)];
    }
    for (std::size_t index = 0; index < counts.size(); ++index) {
        if (counts[index] > 0) {
            const double stored = static_cast<double>(static_cast<std::int64_t>(index) + lowest);
            histogram.bins[bin_index(volume.rescale.apply(stored), histogram)] += counts[index];
        }
    }
}

}  // namespace

std::size_t bytes_per_voxel(VoxelType type) {
    switch (type) {
        case VoxelType::uint8:
            return 1;
        case VoxelType::uint16:
        case VoxelType::int16:
            return 2;
        case VoxelType::float32:
            return 4;
    }
    PENUMBRA_ASSERT(false, "unknown VoxelType");
}

const char* to_string(VoxelType type) {
    switch (type) {
        case VoxelType::uint8:
            return "uint8";
        case VoxelType::uint16:
            return "uint16";
        case VoxelType::int16:
            return "int16";
        case VoxelType::float32:
            return "float32";
    }
    PENUMBRA_ASSERT(false, "unknown VoxelType");
}

double Volume::value(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
    PENUMBRA_ASSERT(x < dims.x && y < dims.y && z < dims.z, "Volume::value outside the volume");
    const std::size_t index =
            (static_cast<std::size_t>(z) * dims.y + y) * static_cast<std::size_t>(dims.x) + x;
    PENUMBRA_ASSERT((index + 1) * bytes_per_voxel(type) <= data.size(),
                    "Volume::data is smaller than dims imply");
    switch (type) {
        case VoxelType::uint8:
            return rescale.apply(load_sample<std::uint8_t>(data, index));
        case VoxelType::uint16:
            return rescale.apply(load_sample<std::uint16_t>(data, index));
        case VoxelType::int16:
            return rescale.apply(load_sample<std::int16_t>(data, index));
        case VoxelType::float32:
            return rescale.apply(load_sample<float>(data, index));
    }
    PENUMBRA_ASSERT(false, "unknown VoxelType");
}

base::Result<Volume> make_volume(std::string name, glm::uvec3 dims, glm::dvec3 spacing,
                                 VoxelType type, std::vector<std::byte> data, Rescale rescale) {
    if (!std::isfinite(rescale.slope) || rescale.slope == 0.0 ||
        !std::isfinite(rescale.intercept)) {
        return invalid(
                "the rescale slope must be finite and non-zero and the intercept finite, "
                "got " + std::to_string(rescale.slope) +
                        " and " + std::to_string(rescale.intercept),
                name);
    }
    if (dims.x == 0 || dims.y == 0 || dims.z == 0) {
        return invalid("every dimension must be at least 1, got " + std::to_string(dims.x) + "x" +
                               std::to_string(dims.y) + "x" + std::to_string(dims.z),
                       name);
    }
    const std::uint64_t voxels = std::uint64_t{dims.x} * dims.y * dims.z;
    if (voxels > max_voxels) {
        return base::make_error(base::ErrorCode::too_large,
                                std::to_string(voxels) + " voxels exceed the limit of " +
                                        std::to_string(max_voxels),
                                name);
    }
    for (int axis = 0; axis < 3; ++axis) {
        if (!std::isfinite(spacing[axis]) || spacing[axis] <= 0.0) {
            return invalid("spacing must be finite and positive, got " +
                                   std::to_string(spacing[axis]) + " on axis " +
                                   std::to_string(axis),
                           name);
        }
    }
    const std::uint64_t expected = voxels * bytes_per_voxel(type);
    if (data.size() != expected) {
        return invalid(std::to_string(data.size()) + " bytes of data for " +
                               std::to_string(voxels) + " " + to_string(type) + " voxels (" +
                               std::to_string(expected) + " bytes expected)",
                       name);
    }

    Volume volume;
    volume.name = std::move(name);
    volume.dims = dims;
    volume.spacing = spacing;
    volume.type = type;
    volume.data = std::move(data);
    volume.rescale = rescale;
    switch (type) {
        case VoxelType::uint8:
            volume.range = integer_range<std::uint8_t>(volume.data, rescale);
            break;
        case VoxelType::uint16:
            volume.range = integer_range<std::uint16_t>(volume.data, rescale);
            break;
        case VoxelType::int16:
            volume.range = integer_range<std::int16_t>(volume.data, rescale);
            break;
        case VoxelType::float32: {
            ValueRange stored;
            volume.nonfinite_voxels = sanitise_float32(volume.data, stored);
            const double a = rescale.apply(stored.min);
            const double b = rescale.apply(stored.max);
            volume.range = {std::min(a, b), std::max(a, b)};
            break;
        }
    }
    return volume;
}

PatientBounds patient_bounds(const Volume& volume) {
    PatientBounds bounds{glm::dvec3(std::numeric_limits<double>::infinity()),
                         glm::dvec3(-std::numeric_limits<double>::infinity())};
    const glm::dvec3 last = glm::dvec3(volume.dims) - 1.0;
    for (int corner = 0; corner < 8; ++corner) {
        // Voxel centres are at whole indices: the outer faces lie half a voxel beyond them.
        const glm::dvec3 index((corner & 1) != 0 ? last.x + 0.5 : -0.5,
                               (corner & 2) != 0 ? last.y + 0.5 : -0.5,
                               (corner & 4) != 0 ? last.z + 0.5 : -0.5);
        const glm::dvec3 patient = volume.origin + volume.axes * (volume.spacing * index);
        bounds.min = glm::min(bounds.min, patient);
        bounds.max = glm::max(bounds.max, patient);
    }
    return bounds;
}

glm::dvec3 lps_to_ras(glm::dvec3 lps) {
    return {-lps.x, -lps.y, lps.z};
}

std::string orientation_code(const glm::dmat3& axes) {
    static constexpr std::array<std::array<char, 2>, 3> letters{
            {{'L', 'R'}, {'P', 'A'}, {'I', 'S'}}};
    std::string code;
    for (int column = 0; column < 3; ++column) {
        const glm::dvec3 axis = axes[column];
        int dominant = 0;
        for (int row = 1; row < 3; ++row) {
            if (std::abs(axis[row]) > std::abs(axis[dominant])) {
                dominant = row;
            }
        }
        code += letters[static_cast<std::size_t>(dominant)][axis[dominant] > 0.0 ? 1 : 0];
    }
    return code;
}

base::Result<Geometry> geometry_from_steps(const glm::dmat3& steps, glm::dvec3 origin) {
    static constexpr std::array<char, 3> index_names{'i', 'j', 'k'};
    Geometry geometry;
    for (int column = 0; column < 3; ++column) {
        const glm::dvec3 step = steps[column];
        const double length = glm::length(step);
        if (!std::isfinite(length) || !(length > 0.0)) {
            return base::make_error(base::ErrorCode::bad_transform,
                                    std::string("the index-to-patient transform's ") +
                                            index_names[static_cast<std::size_t>(column)] +
                                            " column is zero or not finite",
                                    "");
        }
        geometry.spacing[column] = length;
        geometry.axes[column] = step / length;
    }
    for (int a = 0; a < 3; ++a) {
        for (int b = a + 1; b < 3; ++b) {
            const double cosine = glm::dot(geometry.axes[a], geometry.axes[b]);
            if (std::abs(cosine) > max_axis_cosine) {
                char angle[32];
                std::snprintf(angle, sizeof angle, "%.3g",
                              std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / std::numbers::pi);
                return base::make_error(
                        base::ErrorCode::sheared_transform,
                        std::string("the index axes ") + index_names[static_cast<std::size_t>(a)] +
                                " and " + index_names[static_cast<std::size_t>(b)] + " are " +
                                angle +
                                " degrees apart, not perpendicular (a gantry-tilted or sheared "
                                "acquisition)",
                        "");
            }
        }
    }
    if (!std::isfinite(origin.x) || !std::isfinite(origin.y) || !std::isfinite(origin.z)) {
        return base::make_error(base::ErrorCode::bad_transform,
                                "the origin of the index-to-patient transform is "
                                "not finite",
                                "");
    }
    geometry.origin = origin;
    return geometry;
}

base::Result<Volume> make_volume(std::string name, glm::uvec3 dims, glm::dvec3 spacing,
                                 const std::vector<float>& values) {
    std::vector<std::byte> data(values.size() * sizeof(float));
    if (!values.empty()) {
        std::memcpy(data.data(), values.data(), data.size());
    }
    return make_volume(std::move(name), dims, spacing, VoxelType::float32, std::move(data));
}

Histogram compute_histogram(const Volume& volume, std::size_t bin_count) {
    PENUMBRA_ASSERT(bin_count > 0, "a histogram needs at least one bin");
    PENUMBRA_ASSERT(volume.data.size() == volume.voxel_count() * bytes_per_voxel(volume.type),
                    "Volume::data does not match its dims");
    Histogram histogram;
    histogram.range = volume.range;
    histogram.bins.assign(bin_count, 0);
    switch (volume.type) {
        case VoxelType::uint8:
            histogram_of_integers<std::uint8_t>(volume, histogram);
            break;
        case VoxelType::uint16:
            histogram_of_integers<std::uint16_t>(volume, histogram);
            break;
        case VoxelType::int16:
            histogram_of_integers<std::int16_t>(volume, histogram);
            break;
        case VoxelType::float32: {
            const std::size_t count = volume.voxel_count();
            for (std::size_t i = 0; i < count; ++i) {
                const double value = volume.rescale.apply(load_sample<float>(volume.data, i));
                ++histogram.bins[bin_index(value, histogram)];
            }
            break;
        }
    }
    return histogram;
}

namespace {

using Loader = base::Result<Volume> (*)(const std::filesystem::path&, const LoadOptions&);

struct FileFormat {
    std::string_view suffix;  // lower case
    Loader loader;
};

// The one list of volume file names: load_volume picks by it, serve lists files by it.
constexpr FileFormat file_formats[] =
        {
                {".nii", load_nifti}, {".nii.gz", load_nifti}, {".nrrd", load_nrrd},
                {".nhdr", load_nrrd}, {".raw", load_raw},      {".raw.gz", load_raw},
                {".hdr", load_nifti},  // with its .img beside it
};

constexpr std::string_view dicom_suffixes[] = {".dcm", ".dicom"};

}  // namespace

const std::vector<std::string_view>& volume_suffixes() {
    static const std::vector<std::string_view> suffixes = [] {
        std::vector<std::string_view> all;
        for (const FileFormat& format : file_formats) {
            all.push_back(format.suffix);
        }
        return all;
    }();
    return suffixes;
}

bool is_volume_file_name(const std::filesystem::path& path) {
    const std::string name = detail::lower_file_name(path);
    return std::any_of(std::begin(file_formats), std::end(file_formats),
                       [&](const FileFormat& f) { return detail::has_suffix(name, f.suffix); });
}

base::Result<Volume> load_volume(const std::filesystem::path& path, const LoadOptions& options) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
        return load_dicom(path, options);
    }
    const std::string name = detail::lower_file_name(path);
    using detail::has_suffix;
    const auto pick = [&]() -> Loader {
        for (const FileFormat& format : file_formats) {
            if (has_suffix(name, format.suffix)) {
                return format.loader;
            }
        }
        // DICOM file names are often bare UIDs or IM0001, so the content decides too.
        for (const std::string_view suffix : dicom_suffixes) {
            if (has_suffix(name, suffix)) {
                return load_dicom;
            }
        }
        return is_dicom_file(path) ? load_dicom : nullptr;
    }();
    if (pick == nullptr) {
        std::string supported;
        for (const FileFormat& format : file_formats) {
            supported += std::string(format.suffix) + ", ";
        }
        return base::make_error(
                base::ErrorCode::unknown_format,
                "unknown volume file type; supported: " + supported +
                        "(.hdr with its .img; raw: name_XxYxZ_type.raw), DICOM files and folders",
                detail::at_file(path));
    }
    if (auto size = detail::regular_file_size(path); !size) {
        return size.error();
    }
    return pick(path, options);
}

}  // namespace penumbra::volume
