// Reading one DICOM file's header into an Image. Whether a volume can hold the image (one sample
// per pixel, 8, 16 or 32 bits, a frame count within the limits, a mosaic that tiles) is decided
// here, file by file, so that a folder can pass over an image of another kind and open the series
// beside it.

#include "dicom_image.hpp"

#include "dicom_frames.hpp"
#include "dicom_mosaic.hpp"
#include "dicom_tags.hpp"
#include "file_io.hpp"

#include <penumbra/volume/volume.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <utility>

namespace penumbra::volume::detail::dicom {
namespace {

base::Result<PixelFormat> read_pixel_format(DcmDataset& dataset,
                                            const std::filesystem::path& path) {
    PixelFormat format;
    for (auto [key, field] :
         {std::pair{DCM_Rows, &format.rows}, std::pair{DCM_Columns, &format.columns},
          std::pair{DCM_BitsAllocated, &format.bits_allocated}}) {
        const auto value = get_uint16(dataset, key);
        if (!value) {
            return missing_tag(key, path);
        }
        *field = *value;
    }
    format.samples_per_pixel = get_uint16(dataset, DCM_SamplesPerPixel).value_or(1);
    format.bits_stored = get_uint16(dataset, DCM_BitsStored).value_or(format.bits_allocated);
    format.high_bit = get_uint16(dataset, DCM_HighBit).value_or(format.bits_stored - 1);
    format.is_signed = get_uint16(dataset, DCM_PixelRepresentation).value_or(0) == 1;
    format.inverted = get_string(dataset, DCM_PhotometricInterpretation) == "MONOCHROME1";

    const auto unsupported = [&](const std::string& what) {
        return base::make_error(base::ErrorCode::unsupported_type, what, detail::at_file(path));
    };
    if (format.rows == 0 || format.columns == 0) {
        return base::make_error(base::ErrorCode::bad_header,
                                "an image of " + std::to_string(format.columns) + "x" +
                                        std::to_string(format.rows) + " pixels",
                                detail::at_file(path));
    }
    if (format.samples_per_pixel != 1) {
        return unsupported(std::to_string(format.samples_per_pixel) +
                           " samples per pixel (colour images) are not supported; a volume "
                           "needs one sample per pixel");
    }
    if (format.bits_allocated != 8 && format.bits_allocated != 16 && format.bits_allocated != 32) {
        return unsupported(std::to_string(format.bits_allocated) +
                           " bits allocated per pixel are not supported; 8, 16 and 32 are");
    }
    if (format.bits_stored == 0 || format.bits_stored > format.bits_allocated ||
        format.high_bit >= format.bits_allocated || format.high_bit + 1 < format.bits_stored) {
        return base::make_error(base::ErrorCode::bad_header,
                                "BitsStored " + std::to_string(format.bits_stored) +
                                        " and HighBit " + std::to_string(format.high_bit) +
                                        " do not fit in BitsAllocated " +
                                        std::to_string(format.bits_allocated),
                                detail::at_file(path));
    }
    return format;
}

}  // namespace

base::Result<Opened> open_image(const std::filesystem::path& path, Image& image) {
    image.path = path;
    image.file = std::make_unique<DcmFileFormat>();
    const OFCondition status = image.file->loadFile(path.c_str());
    if (status.bad()) {
        const std::string reason = std::string(" (DCMTK: ") + status.text() + ")";
        if (!is_dicom_file(path)) {
            return base::make_error(base::ErrorCode::not_dicom,
                                    "not a DICOM file: no DICM marker after the 128-byte "
                                    "preamble, and not readable as a bare data set" +
                                            reason,
                                    detail::at_file(path));
        }
        // DCMTK reports a file that ends inside an element as one of these two.
        if (status == EC_StreamNotifyClient || status == EC_InvalidStream) {
            return base::make_error(base::ErrorCode::truncated,
                                    "the file ends before the data its elements announce "
                                    "(truncated or damaged)" +
                                            reason,
                                    detail::at_file(path));
        }
        return base::make_error(base::ErrorCode::bad_header, "DCMTK cannot parse the file" + reason,
                                detail::at_file(path));
    }
    DcmDataset& dataset = *image.file->getDataset();
    if (!dataset.tagExists(DCM_PixelData)) {
        if (dataset.tagExists(DCM_FloatPixelData) || dataset.tagExists(DCM_DoubleFloatPixelData)) {
            return base::make_error(base::ErrorCode::unsupported_type,
                                    "float pixel data is not supported; integer PixelData is",
                                    detail::at_file(path));
        }
        return Opened::not_an_image;
    }
    auto format = read_pixel_format(dataset, path);
    if (!format) {
        return format.error();
    }
    image.format = *format;
    const auto frames = get_int(dataset, DCM_NumberOfFrames).value_or(1);
    if (frames < 1) {
        return base::make_error(base::ErrorCode::bad_header,
                                "NumberOfFrames is " + std::to_string(frames),
                                detail::at_file(path));
    }
    // Checked before the frames' positions are read: a header claiming billions of frames must
    // cost no memory.
    const std::uint64_t frame_voxels = std::uint64_t{image.format.rows} * image.format.columns;
    if (static_cast<std::uint64_t>(frames) > max_frames ||
        static_cast<std::uint64_t>(frames) > max_voxels / frame_voxels) {
        return base::make_error(base::ErrorCode::too_large,
                                "NumberOfFrames " + std::to_string(frames) + " of " +
                                        format->describe() + " exceeds the limit of " +
                                        std::to_string(max_frames) + " frames or " +
                                        std::to_string(max_voxels) + " voxels",
                                detail::at_file(path));
    }
    image.frame_count = static_cast<std::uint32_t>(frames);
    auto mosaic = read_mosaic(dataset, image.format, image.frame_count, path);
    if (!mosaic) {
        return mosaic.error();
    }
    image.mosaic = *mosaic;
    for (const Frame& frame :
         read_frames(dataset, 0, image.frame_count, image.mosaic, image.format)) {
        if (!frame.position || !frame.orientation) {
            image.frame_depths.clear();
            break;
        }
        const glm::dvec3 normal = slice_normal(*frame.orientation);
        image.frame_depths.push_back(glm::dot(normal, *frame.position) /
                                     std::max(glm::length(normal), 1e-12));
    }
    image.series_uid = get_string(dataset, DCM_SeriesInstanceUID);
    if (const auto number = get_int(dataset, DCM_SeriesNumber)) {
        image.series_number = std::to_string(*number);
    }
    image.series_description = get_string(dataset, DCM_SeriesDescription);
    image.modality = get_string(dataset, DCM_Modality);
    image.hounsfield = get_string(dataset, DCM_Modality) == "CT" ||
                       get_string(dataset, DCM_RescaleType) == "HU";
    return Opened::image;
}

}  // namespace penumbra::volume::detail::dicom
