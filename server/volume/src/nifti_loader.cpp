// NIfTI-1 and NIfTI-2 (.nii, .nii.gz) through the reference nifti library (Debian's libnifti2),
// which also handles gzip, byte order and the header's many legacy corners.
//
// Rules this loader adds on top of the library:
//   - Only the first 3-D volume is read. A 4-D or 5-D file (fMRI time series, vector fields)
//     loads its first volume and the log says how many were left out.
//   - Spacing is |dx|, |dy|, |dz|. A spacing of 0 or a non-finite one (common in files written
//     by tools that leave pixdim empty) becomes 1 with a log warning, so the data stays viewable.
//   - uint8 and uint16 are kept; every other scalar type becomes float32. A scale
//     (scl_slope finite and non-zero, and not the identity slope 1 with intercept 0) is applied
//     as value * slope + intercept in double and stored as float32; a non-finite intercept
//     counts as 0.
//   - The library itself sets NaN and ±Inf float voxels to 0 while reading, so a NIfTI volume
//     never reports non-finite voxels: they arrive as 0, not as the finite minimum.

#include "file_io.hpp"
#include "file_name.hpp"
#include "samples.hpp"

#include <penumbra/base/log.hpp>
#include <penumbra/volume/volume.hpp>

#include <nifti2_io.h>

#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <string_view>

namespace penumbra::volume {
namespace {

constexpr std::string_view log_component = "volume";

struct ImageFree {
    void operator()(nifti_image* image) const { nifti_image_free(image); }
};

using Image = std::unique_ptr<nifti_image, ImageFree>;

struct BrickList {
    nifti_brick_list list{};

    ~BrickList() { nifti_free_NBL(&list); }
};

// The library prints its own diagnostics on stderr at its default debug level; Penumbra reports
// failures as Errors instead, so it is silenced once per process.
void quiet_library() {
    static std::once_flag once;
    std::call_once(once, [] { nifti_set_debug_level(0); });
}

std::optional<detail::SampleType> sample_type_of(int datatype) {
    using detail::SampleType;
    switch (datatype) {
        case DT_UINT8:
            return SampleType::uint8;
        case DT_INT8:
            return SampleType::int8;
        case DT_INT16:
            return SampleType::int16;
        case DT_UINT16:
            return SampleType::uint16;
        case DT_INT32:
            return SampleType::int32;
        case DT_UINT32:
            return SampleType::uint32;
        case DT_INT64:
            return SampleType::int64;
        case DT_UINT64:
            return SampleType::uint64;
        case DT_FLOAT32:
            return SampleType::float32;
        case DT_FLOAT64:
            return SampleType::float64;
        default:
            return std::nullopt;
    }
}

double spacing_or_one(double spacing, char axis, const std::filesystem::path& path) {
    const double size = std::abs(spacing);
    if (std::isfinite(size) && size > 0.0) {
        return size;
    }
    base::log_warning(log_component, path.string() + ": voxel size d" + axis + " is " +
                                             std::to_string(spacing) + "; using 1");
    return 1.0;
}

// Checks that an uncompressed file holds the first volume's data. The library would find out as
// well, but it prints its own complaint on stderr and cannot say how short the file is.
base::Status check_plain_size(const std::filesystem::path& path, std::uint64_t data_offset,
                              std::uint64_t bytes) {
    auto file = detail::open_file(path);
    if (!file) {
        return file.error();
    }
    std::array<std::byte, 2> magic{};
    auto got = detail::read_some(file->get(), path, 0, magic);
    if (!got) {
        return got.error();
    }
    if (*got == 2 && magic[0] == std::byte{0x1f} && magic[1] == std::byte{0x8b}) {
        return base::Ok{};  // gzip data, whatever the name says: the library inflates it
    }
    auto size = detail::regular_file_size(path);
    if (!size) {
        return size.error();
    }
    if (*size < data_offset || *size - data_offset < bytes) {
        return base::make_error("truncated",
                                "expected " + std::to_string(bytes) +
                                        " bytes of voxel data from byte " +
                                        std::to_string(data_offset) + ", the file holds " +
                                        std::to_string(*size) + " bytes",
                                detail::at_byte(path, *size));
    }
    return base::Ok{};
}

}  // namespace

base::Result<Volume> load_nifti(const std::filesystem::path& path) {
    const std::string lower = detail::lower_file_name(path);
    if (!detail::has_suffix(lower, ".nii") && !detail::has_suffix(lower, ".nii.gz")) {
        return base::make_error("bad_file_name", "a NIfTI file name must end in .nii or .nii.gz",
                                detail::at_file(path));
    }
    if (auto size = detail::regular_file_size(path); !size) {
        return size.error();
    }
    quiet_library();

    // The header first, alone, so that absurd dimensions are rejected before any allocation.
    Image image(nifti_image_read(path.c_str(), 0));
    if (!image) {
        return base::make_error("bad_header",
                                "not a readable NIfTI-1 or NIfTI-2 file (the nifti library "
                                "rejected its header)",
                                detail::at_file(path));
    }
    const auto extent = [](std::int64_t n) { return n < 1 ? std::int64_t{1} : n; };
    const std::array<std::int64_t, 3> sizes{extent(image->nx), extent(image->ny),
                                            extent(image->nz)};
    std::uint64_t voxels = 1;
    for (const std::int64_t size : sizes) {
        if (static_cast<std::uint64_t>(size) > max_voxels / voxels) {
            return base::make_error("too_large",
                                    "dimensions " + std::to_string(image->nx) + "x" +
                                            std::to_string(image->ny) + "x" +
                                            std::to_string(image->nz) + " exceed the limit of " +
                                            std::to_string(max_voxels) + " voxels",
                                    detail::at_file(path));
        }
        voxels *= static_cast<std::uint64_t>(size);
    }
    const auto type = sample_type_of(image->datatype);
    if (!type) {
        return base::make_error("unsupported_type",
                                std::string("NIfTI datatype ") +
                                        nifti_datatype_string(image->datatype) + " (" +
                                        std::to_string(image->datatype) +
                                        ") is not supported; scalar integer and float types are",
                                detail::at_file(path));
    }
    if (static_cast<std::size_t>(image->nbyper) != detail::sample_size(*type)) {
        return base::make_error("bad_header",
                                "bytes per voxel " + std::to_string(image->nbyper) +
                                        " do not match datatype " +
                                        nifti_datatype_string(image->datatype),
                                detail::at_file(path));
    }
    const std::int64_t volumes =
            extent(image->nt) * extent(image->nu) * extent(image->nv) * extent(image->nw);
    if (volumes > 1) {
        base::log_info(log_component, path.string() + ": " + std::to_string(volumes) +
                                              " volumes in the file; loading the first");
    }

    const std::uint64_t bytes = voxels * detail::sample_size(*type);
    if (image->iname_offset < 0) {
        return base::make_error("bad_header",
                                "negative data offset " + std::to_string(image->iname_offset),
                                detail::at_file(path));
    }
    if (auto status =
                check_plain_size(path, static_cast<std::uint64_t>(image->iname_offset), bytes);
        !status) {
        return status.error();
    }

    BrickList bricks;
    const std::int64_t first_volume = 0;
    if (nifti_image_load_bricks(image.get(), 1, &first_volume, &bricks.list) <= 0 ||
        bricks.list.nbricks < 1 || bricks.list.bricks == nullptr ||
        bricks.list.bricks[0] == nullptr) {
        return base::make_error("truncated",
                                "the nifti library could not read the voxel data (the file is "
                                "truncated or its data offset is wrong)",
                                detail::at_file(path));
    }
    if (static_cast<std::uint64_t>(bricks.list.bsize) != bytes) {
        return base::make_error("bad_header",
                                "the library read " + std::to_string(bricks.list.bsize) +
                                        " bytes for a volume of " + std::to_string(bytes),
                                detail::at_file(path));
    }
    const auto* first = static_cast<const std::byte*>(bricks.list.bricks[0]);
    const std::span<const std::byte> samples(first, bytes);

    const double slope = image->scl_slope;
    const double inter = std::isfinite(image->scl_inter) ? image->scl_inter : 0.0;
    const bool scaled = std::isfinite(slope) && slope != 0.0 && !(slope == 1.0 && inter == 0.0);

    VoxelType stored = detail::stored_type(*type);
    std::vector<std::byte> data;
    if (scaled) {
        stored = VoxelType::float32;
        data = detail::to_float32(*type, samples, slope, inter);
    } else if (detail::is_kept(*type)) {
        data.assign(samples.begin(), samples.end());
    } else {
        data = detail::to_float32(*type, samples);
    }

    const glm::dvec3 spacing(spacing_or_one(image->dx, 'x', path),
                             spacing_or_one(image->dy, 'y', path),
                             spacing_or_one(image->dz, 'z', path));
    const std::string name =
            detail::strip_suffix(path, std::array<std::string_view, 2>{".nii.gz", ".nii"});
    auto volume = make_volume(
            name,
            glm::uvec3(static_cast<std::uint32_t>(sizes[0]), static_cast<std::uint32_t>(sizes[1]),
                       static_cast<std::uint32_t>(sizes[2])),
            spacing, stored, std::move(data));
    if (!volume) {
        base::Error error = volume.error();
        error.where = detail::at_file(path);
        return error;
    }
    return volume;
}

}  // namespace penumbra::volume
