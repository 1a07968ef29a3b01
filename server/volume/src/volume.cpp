#include "file_io.hpp"
#include "file_name.hpp"

#include <penumbra/volume/volume.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
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
    return base::make_error("invalid_volume", std::move(message), name);
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
ValueRange integer_range(const std::vector<std::byte>& data) {
    const std::size_t count = data.size() / sizeof(T);
    T lo = std::numeric_limits<T>::max();
    T hi = std::numeric_limits<T>::lowest();
    for (std::size_t i = 0; i < count; ++i) {
        const T v = load_sample<T>(data, i);
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
    return {static_cast<double>(lo), static_cast<double>(hi)};
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

// Counts each of the 2^bits possible integer values once, then spreads the counts over the bins:
// far cheaper than a division per voxel for the common 8- and 16-bit volumes.
template <class T>
void histogram_of_integers(const Volume& volume, Histogram& histogram) {
    std::vector<std::uint64_t> counts(std::size_t{1} << (8 * sizeof(T)), 0);
    const std::size_t count = volume.voxel_count();
    for (std::size_t i = 0; i < count; ++i) {
        ++counts[load_sample<T>(volume.data, i)];
    }
    for (std::size_t value = 0; value < counts.size(); ++value) {
        if (counts[value] > 0) {
            histogram.bins[bin_index(static_cast<double>(value), histogram)] += counts[value];
        }
    }
}

}  // namespace

std::size_t bytes_per_voxel(VoxelType type) {
    switch (type) {
        case VoxelType::uint8:
            return 1;
        case VoxelType::uint16:
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
            return load_sample<std::uint8_t>(data, index);
        case VoxelType::uint16:
            return load_sample<std::uint16_t>(data, index);
        case VoxelType::float32:
            return load_sample<float>(data, index);
    }
    PENUMBRA_ASSERT(false, "unknown VoxelType");
}

base::Result<Volume> make_volume(std::string name, glm::uvec3 dims, glm::dvec3 spacing,
                                 VoxelType type, std::vector<std::byte> data) {
    if (dims.x == 0 || dims.y == 0 || dims.z == 0) {
        return invalid("every dimension must be at least 1, got " + std::to_string(dims.x) + "x" +
                               std::to_string(dims.y) + "x" + std::to_string(dims.z),
                       name);
    }
    const std::uint64_t voxels = std::uint64_t{dims.x} * dims.y * dims.z;
    if (voxels > max_voxels) {
        return base::make_error("too_large",
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
    switch (type) {
        case VoxelType::uint8:
            volume.range = integer_range<std::uint8_t>(volume.data);
            break;
        case VoxelType::uint16:
            volume.range = integer_range<std::uint16_t>(volume.data);
            break;
        case VoxelType::float32:
            volume.nonfinite_voxels = sanitise_float32(volume.data, volume.range);
            break;
    }
    return volume;
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
        case VoxelType::float32: {
            const std::size_t count = volume.voxel_count();
            for (std::size_t i = 0; i < count; ++i) {
                ++histogram.bins[bin_index(load_sample<float>(volume.data, i), histogram)];
            }
            break;
        }
    }
    return histogram;
}

base::Result<Volume> load_volume(const std::filesystem::path& path, const LoadOptions& options) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
        return load_dicom(path, options);
    }
    const std::string name = detail::lower_file_name(path);
    using detail::has_suffix;
    using Loader = base::Result<Volume> (*)(const std::filesystem::path&, const LoadOptions&);
    const auto pick = [&]() -> Loader {
        if (has_suffix(name, ".nii") || has_suffix(name, ".nii.gz") || has_suffix(name, ".hdr")) {
            return load_nifti;
        }
        if (has_suffix(name, ".nrrd") || has_suffix(name, ".nhdr")) {
            return load_nrrd;
        }
        if (has_suffix(name, ".raw") || has_suffix(name, ".raw.gz")) {
            return load_raw;
        }
        // DICOM file names are often bare UIDs or IM0001, so the content decides too.
        if (has_suffix(name, ".dcm") || has_suffix(name, ".dicom") || is_dicom_file(path)) {
            return load_dicom;
        }
        return nullptr;
    }();
    if (pick == nullptr) {
        return base::make_error("unknown_format",
                                "unknown volume file type; supported: .nii, .nii.gz, .hdr "
                                "(with its .img), .nrrd, .nhdr, .raw, .raw.gz "
                                "(name_XxYxZ_type.raw), DICOM files and folders",
                                detail::at_file(path));
    }
    if (auto size = detail::regular_file_size(path); !size) {
        return size.error();
    }
    return pick(path, options);
}

}  // namespace penumbra::volume
