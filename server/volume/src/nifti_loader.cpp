// NIfTI-1 and NIfTI-2 (.nii, .nii.gz): the header through the reference nifti library (Debian's
// libnifti2), which handles its many legacy corners; the voxel data read here, straight into the
// volume (the library would read it into a buffer of its own, a second copy of the volume).
//
// Rules this loader adds on top of the library:
//   - Only the first 3-D volume is read. A 4-D or 5-D file (fMRI time series, vector fields)
//     loads its first volume and the log says how many were left out.
//   - Axes, origin and spacing come from the sform when its code is set, else the qform (see
//     patient_geometry); spacing is the length of each transform column. A voxel size of 0 or a
//     non-finite one (common in files written by tools that leave pixdim empty) becomes 1 with a
//     log warning, so the data stays viewable.
//   - uint8, uint16 and int16 are kept; every other scalar type becomes float32. A scale
//     (scl_slope finite and non-zero, and not the identity slope 1 with intercept 0) of whole
//     numbers on a kept integer type stays Volume::rescale (the data is not widened); any other
//     is applied as value * slope + intercept in double and stored as float32; a non-finite
//     intercept counts as 0.
//   - intent_name "HU" marks the values as Hounsfield units (Volume::hounsfield).
//   - NaN and ±Inf float voxels become the finite minimum and are counted, as in every format.

#include "file_io.hpp"
#include "file_name.hpp"
#include "memory_budget.hpp"
#include "samples.hpp"

#include <penumbra/base/log.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/geometric.hpp>
#include <nifti2_io.h>

#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
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

// The library prints its own diagnostics on stderr at its default debug level; Penumbra reports
// failures as Errors instead, so it is silenced once per process.
void quiet_library() {
    static std::once_flag once;
    std::call_once(once, [] { nifti_set_debug_level(0); });
}

// What the data of a NIfTI intent that holds no image of space are (point sets, surfaces'
// triangles and node indices, CIFTI-2's arrays over brainordinates, codes 3000-3099), which
// opened as a volume would show a meaningless 1-voxel-thick grid; nullopt for every other intent.
// Matrices and shapes are not among them: a tensor volume (ITK's, FSL's) is a grid of matrices,
// whose first component opens as any 5-D file's does.
std::optional<std::string> non_volume_intent(int code) {
    switch (code) {
        case NIFTI_INTENT_POINTSET:
            return "a point set (intent " + std::to_string(code) + ")";
        case NIFTI_INTENT_TRIANGLE:
            return "a surface's triangles (intent " + std::to_string(code) + ")";
        case NIFTI_INTENT_NODE_INDEX:
            return "a surface's node indices (intent " + std::to_string(code) + ")";
        default:
            break;
    }
    if (code >= 3000 && code < 3100) {
        return "CIFTI-2 data over brainordinates, such as a connectivity matrix (intent " +
               std::to_string(code) + ")";
    }
    return std::nullopt;
}

// The header alone (and its extensions), no voxels.
base::Result<Image> read_header(const std::filesystem::path& path) {
    quiet_library();
    Image image(nifti_image_read(path.c_str(), 0));
    if (!image) {
        return base::make_error(base::ErrorCode::bad_header,
                                "not a readable NIfTI-1 or NIfTI-2 file (the nifti library "
                                "rejected its header)",
                                detail::at_file(path));
    }
    return image;
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

// The index-to-patient transform, which NIfTI defines in RAS millimetres: the sform when its
// code is set, else the qform (the library builds it from the quaternion, pixdim and qfac; with
// qform_code 0 it is diag(dx, dy, dz), NIfTI's "method 1"). A sheared sform falls back to a set
// qform, which cannot shear, as ITK does; without a usable one the sheared sform is resampled
// (place_volume). A zero or non-finite voxel size leaves its axis unrotated with size 1, as
// spacing_or_one says.
base::Result<Geometry> patient_geometry(const nifti_image& image,
                                        const std::filesystem::path& path) {
    const auto transform = [&](const nifti_dmat44& m) {
        glm::dmat3 steps(1.0);
        for (int column = 0; column < 3; ++column) {
            steps[column] = glm::dvec3(m.m[0][column], m.m[1][column], m.m[2][column]);
        }
        return std::pair{steps, glm::dvec3(m.m[0][3], m.m[1][3], m.m[2][3])};
    };
    const auto geometry_of = [&](const nifti_dmat44& m) {
        auto [steps, origin] = transform(m);
        const std::array<double, 3> sizes{image.dx, image.dy, image.dz};
        for (int column = 0; column < 3; ++column) {
            const double length = glm::length(steps[column]);
            if (!std::isfinite(length) || !(length > 0.0)) {
                glm::dvec3 unit(0.0);
                unit[column] = 1.0;
                steps[column] = unit * spacing_or_one(sizes[static_cast<std::size_t>(column)],
                                                      "xyz"[column], path);
            }
        }
        return placed_geometry(steps, origin);
    };
    if (image.sform_code > 0) {
        auto sform = geometry_of(image.sto_xyz);
        if (!sform && image.qform_code <= 0) {
            base::Error error = sform.error();
            error.message = "the sform " + error.message;
            error.where = detail::at_file(path);
            return error;
        }
        if (sform && (!sform->sheared_steps || image.qform_code <= 0)) {
            return sform;  // a sheared sform without a qform is resampled (place_volume)
        }
    }
    auto qform = geometry_of(image.qto_xyz);
    if (!qform && image.sform_code > 0) {
        if (auto sform = geometry_of(image.sto_xyz)) {
            return sform;  // sheared, resampled rather than refused for want of a qform
        }
    }
    if (!qform) {
        base::Error error = qform.error();
        error.where = detail::at_file(path);
        return error;
    }
    if (image.sform_code > 0) {
        auto sform = geometry_of(image.sto_xyz);
        qform->note = std::string("the sform is not a rotation (") +
                      (sform ? std::string("its axes are sheared") : sform.error().message) +
                      "): the qform places the voxels, as ITK does";
        base::log_warning(log_component, path.string() + ": " + qform->note);
    }
    return qform;
}

// Reads the first volume's samples from the data file: plain bytes from `data_offset`, or, when
// the file is gzip data (whatever its name says), the same offset in the decompressed stream.
base::Status read_samples(const std::filesystem::path& path, std::uint64_t data_offset,
                          detail::SampleSink& sink, std::uint64_t bytes) {
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
        if (auto status = detail::seek_to(file->get(), path, 0); !status) {
            return status.error();
        }
        auto inflated = detail::inflate_file(file->get(), path, 0, data_offset, sink);
        if (!inflated) {
            return inflated.error();
        }
        if (inflated->produced < bytes) {
            return base::make_error(
                    base::ErrorCode::truncated,
                    "expected " + std::to_string(bytes) + " bytes of voxel data from byte " +
                            std::to_string(data_offset) + " of the decompressed data, got " +
                            std::to_string(inflated->produced),
                    detail::at_file(path));
        }
        return base::Ok{};
    }
    auto size = detail::regular_file_size(path);
    if (!size) {
        return size.error();
    }
    if (*size < data_offset || *size - data_offset < bytes) {
        return base::make_error(base::ErrorCode::truncated,
                                "expected " + std::to_string(bytes) +
                                        " bytes of voxel data from byte " +
                                        std::to_string(data_offset) + ", the file holds " +
                                        std::to_string(*size) + " bytes",
                                detail::at_byte(path, *size));
    }
    if (auto status = detail::seek_to(file->get(), path, data_offset); !status) {
        return status.error();
    }
    auto read = detail::read_into(file->get(), path, data_offset, sink);
    if (!read) {
        return read.error();
    }
    if (*read != bytes) {
        return base::make_error(base::ErrorCode::truncated,
                                "the file ended after " + std::to_string(*read) + " of " +
                                        std::to_string(bytes) + " bytes of voxel data",
                                detail::at_byte(path, data_offset + *read));
    }
    return base::Ok{};
}

base::Result<Volume> load_nifti_file(const std::filesystem::path& path,
                                     const LoadOptions& options) {
    const std::string lower = detail::lower_file_name(path);
    if (!detail::has_suffix(lower, ".nii") && !detail::has_suffix(lower, ".nii.gz") &&
        !detail::has_suffix(lower, ".hdr")) {
        return base::make_error(base::ErrorCode::bad_file_name,
                                "a NIfTI file name must end in .nii, .nii.gz or .hdr (with its "
                                ".img beside it)",
                                detail::at_file(path));
    }
    if (auto size = detail::regular_file_size(path); !size) {
        return size.error();
    }
    // The header first, alone, so that absurd dimensions are rejected before any allocation.
    auto header = read_header(path);
    if (!header) {
        return header.error();
    }
    Image image = std::move(header.value());
    if (const auto intent = non_volume_intent(image->intent_code)) {
        return base::make_error(base::ErrorCode::unsupported_dimension,
                                "not a volume: the file holds " + *intent, detail::at_file(path));
    }
    const auto extent = [](std::int64_t n) { return n < 1 ? std::int64_t{1} : n; };
    const std::array<std::int64_t, 3> sizes{extent(image->nx), extent(image->ny),
                                            extent(image->nz)};
    std::uint64_t voxels = 1;
    for (const std::int64_t size : sizes) {
        if (static_cast<std::uint64_t>(size) > max_voxels / voxels) {
            return base::make_error(base::ErrorCode::too_large,
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
        return base::make_error(base::ErrorCode::unsupported_type,
                                std::string("NIfTI datatype ") +
                                        nifti_datatype_string(image->datatype) + " (" +
                                        std::to_string(image->datatype) +
                                        ") is not supported; scalar integer and float types are",
                                detail::at_file(path));
    }
    if (static_cast<std::size_t>(image->nbyper) != detail::sample_size(*type)) {
        return base::make_error(base::ErrorCode::bad_header,
                                "bytes per voxel " + std::to_string(image->nbyper) +
                                        " do not match datatype " +
                                        nifti_datatype_string(image->datatype),
                                detail::at_file(path));
    }
    // In double: a hostile header's counts would overflow an integer product.
    const double volumes =
            static_cast<double>(extent(image->nt)) * static_cast<double>(extent(image->nu)) *
            static_cast<double>(extent(image->nv)) * static_cast<double>(extent(image->nw));
    if (volumes > 1.0) {
        char count[32];
        std::snprintf(count, sizeof count, "%.0f", volumes);
        base::log_info(log_component,
                       path.string() + ": " + count + " volumes in the file; loading the first");
    }

    if (image->iname_offset < 0) {
        return base::make_error(base::ErrorCode::bad_header,
                                "negative data offset " + std::to_string(image->iname_offset),
                                detail::at_file(path));
    }
    const double slope = image->scl_slope;
    const double inter = std::isfinite(image->scl_inter) ? image->scl_inter : 0.0;
    const bool scaled = std::isfinite(slope) && slope != 0.0 && !(slope == 1.0 && inter == 0.0);
    const detail::SampleLayout layout{.type = *type,
                                      .voxels = voxels,
                                      // Not the host's order (little endian): big endian.
                                      .big_endian = image->byteorder != nifti_short_order(),
                                      .slope = scaled ? slope : 1.0,
                                      .inter = scaled ? inter : 0.0};
    const std::string what = std::to_string(sizes[0]) + "x" + std::to_string(sizes[1]) + "x" +
                             std::to_string(sizes[2]) + " " + detail::sample_name(*type) +
                             (layout.stored() == detail::stored_type(*type) && !layout.scaled()
                                      ? std::string()
                                      : std::string(" kept as ") + to_string(layout.stored()));
    if (auto status = detail::check_budget(layout.stored_bytes(), what, path, options); !status) {
        return status.error();
    }
    // A two-file header (.hdr/.img, SPM's output; magic "ni1", or Analyze 7.5) keeps its data in
    // the file the library derives from the header's own name, in the same folder.
    const std::filesystem::path data_file = image->iname != nullptr ? image->iname : path;
    detail::SampleSink sink(layout);
    if (auto status = read_samples(data_file, static_cast<std::uint64_t>(image->iname_offset), sink,
                                   layout.file_bytes());
        !status) {
        return status.error();
    }

    auto geometry = patient_geometry(*image, path);
    if (!geometry) {
        return geometry.error();
    }
    const std::string name =
            detail::strip_suffix(path, std::array<std::string_view, 3>{".nii.gz", ".nii", ".hdr"});
    auto volume = make_volume(
            name,
            glm::uvec3(static_cast<std::uint32_t>(sizes[0]), static_cast<std::uint32_t>(sizes[1]),
                       static_cast<std::uint32_t>(sizes[2])),
            geometry->spacing, layout.stored(), sink.take(), layout.rescale());
    if (!volume) {
        base::Error error = volume.error();
        error.where = detail::at_file(path);
        return error;
    }
    if (auto placed = place_volume(*volume, *geometry, options); !placed) {
        base::Error error = placed.error();
        error.where = detail::at_file(path);
        return error;
    }
    // NIfTI has no field for the values' units; intent_name ("name or meaning of data") set to
    // "HU" marks a CT in Hounsfield units.
    const std::string_view intent(image->intent_name);
    volume->hounsfield =
            intent.size() == 2 && std::toupper(intent[0]) == 'H' && std::toupper(intent[1]) == 'U';
    volume->label_intent = image->intent_code == NIFTI_INTENT_LABEL;
    volume->volumes_in_file = static_cast<std::uint64_t>(volumes);
    return volume;
}

}  // namespace

base::Result<Volume> load_nifti(const std::filesystem::path& path, const LoadOptions& options) {
    return detail::guard_allocation(path, [&] { return load_nifti_file(path, options); });
}

base::Result<bool> read_nifti_label_intent(const std::filesystem::path& path) {
    if (auto size = detail::regular_file_size(path); !size) {
        return size.error();
    }
    auto header = read_header(path);
    if (!header) {
        return header.error();
    }
    return header.value()->intent_code == NIFTI_INTENT_LABEL;
}

}  // namespace penumbra::volume
