// DICOM through DCMTK (Debian's libdcmtk): a folder holding the slices of one or more series, or
// one file (a multi-frame image, or a single slice). The entry points here compose the loader's
// parts, each file of which states the rules it adds on top of the library:
//   - dicom_files: which files of a folder are read, and what is said of those passed over;
//   - dicom_image: one file's header, and whether a volume can hold its image;
//   - dicom_series: grouping the images into series and choosing one;
//   - dicom_frames: ordering the frames along the slice normal, their spacing and geometry;
//   - dicom_mosaic: Siemens mosaics and their CSA header;
//   - dicom_pixels: decoding the pixel data into the volume;
//   - dicom_tags: reading values out of DCMTK's data sets.

#include "dicom_files.hpp"
#include "dicom_frames.hpp"
#include "dicom_image.hpp"
#include "dicom_pixels.hpp"
#include "dicom_series.hpp"
#include "dicom_tags.hpp"
#include "file_io.hpp"
#include "file_name.hpp"
#include "memory_budget.hpp"

#include <penumbra/base/log.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/geometric.hpp>

#include <array>
#include <cmath>
#include <mutex>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include <dcmtk/config/osconfig.h>  // must come before the other DCMTK headers
#include <dcmtk/dcmdata/dcdict.h>
#include <dcmtk/dcmdata/dcrledrg.h>
#include <dcmtk/dcmdata/dcvr.h>
#include <dcmtk/dcmjpeg/djdecode.h>
#include <dcmtk/dcmjpls/djdecode.h>
#include <dcmtk/oflog/oflog.h>

namespace penumbra::volume {
namespace detail::dicom {
namespace {

// Codecs are registered once per process and never cleaned up: cleanup would race with another
// thread's load, and the process ends anyway. DCMTK's own log goes to stderr at warning level;
// failures reach the user as Errors instead, so it is silenced. Elements written with the VR UN
// (a converter's way with attributes it does not know, as GDCM's RLE dose grids hold their
// spacing, position and dose scaling) are read with the VR the dictionary gives them, as pydicom
// does.
void prepare_library() {
    static std::once_flag once;
    std::call_once(once, [] {
        OFLog::configure(OFLogger::OFF_LOG_LEVEL);
        dcmEnableUnknownVRConversion.set(OFTrue);
        DJDecoderRegistration::registerCodecs();
        DJLSDecoderRegistration::registerCodecs();
        DcmRLEDecoderRegistration::registerCodecs();
    });
}

base::Result<Volume> load_dicom_folder(const std::filesystem::path& folder,
                                       const LoadOptions& options) {
    auto found = read_folder(folder, options.dicom_subfolders, true);
    if (!found) {
        return found.error();
    }
    if (!found->not_dicom.empty() || found->not_images > 0) {
        base::log_info(log_component, folder.string() + ": skipped " +
                                              std::to_string(found->not_dicom.size()) +
                                              " files that are not DICOM and " +
                                              std::to_string(found->not_images) +
                                              " DICOM files without pixel data");
    }
    std::vector<Image>& images = found->images;
    const std::size_t series_count = series_of(images).size();
    auto chosen = select_series(images, options.dicom_series, folder);
    if (!chosen) {
        return chosen.error();
    }
    // One of several series is named for itself, the only one for its folder.
    std::string name = folder.filename().empty() ? folder.parent_path().filename().string()
                                                 : folder.filename().string();
    if (series_count > 1) {
        name = chosen->label();
    }
    auto volume = assemble(images, name, folder, options);
    if (!volume) {
        base::Error error = volume.error();
        if (error.code == base::ErrorCode::inconsistent_series) {
            error.message += found->damaged_suffix();
        }
        return error;
    }
    // A damaged slice of this series that lay between two slices of the volume leaves a gap that
    // the spacing check cannot see where the slices left are evenly spaced (every other one
    // damaged; two slices have one gap, always "even"): refused, as a gap is. One at a slice's
    // own position (a damaged copy beside the intact file) or past an end takes nothing from
    // between the slices; the note names it.
    const double step = volume->spacing.z;
    const double last_depth = step * static_cast<double>(volume->dims.z - 1);
    for (const FolderImages::Damaged& file : found->damaged) {
        if (file.series_uid != chosen->uid || !file.position || volume->dims.z < 2) {
            continue;
        }
        const glm::dvec3 position((*file.position)[0], (*file.position)[1], (*file.position)[2]);
        const double depth = glm::dot(volume->axes[2], lps_to_ras(position) - volume->origin);
        const double off_grid = std::abs(depth / step - std::round(depth / step));
        if (depth > same_position && depth < last_depth - same_position &&
            off_grid > gap_tolerance) {
            return base::make_error(base::ErrorCode::inconsistent_series,
                                    "the series lacks its slice " + millimetres(depth) +
                                            " from its first along the slice normal, whose "
                                            "file is damaged (" +
                                            std::string(base::name_of(file.error.code)) + ": " +
                                            file.error.message + ")",
                                    file.error.where);
        }
    }
    auto notes = found->notes();
    notes.insert(notes.end(), volume->notes.begin(), volume->notes.end());
    volume->notes = std::move(notes);
    return volume;
}

base::Result<Volume> load_dicom_file(const std::filesystem::path& path,
                                     const LoadOptions& options) {
    if (auto size = detail::regular_file_size(path); !size) {
        return size.error();
    }
    std::vector<Image> images(1);
    auto opened = open_image(path, images.front());
    if (!opened) {
        return opened.error();
    }
    if (*opened == Opened::not_an_image) {
        return missing_tag(DCM_PixelData, path);
    }
    const std::string name =
            detail::strip_suffix(path, std::array<std::string_view, 2>{".dcm", ".dicom"});
    return assemble(images, name, path, options);
}

base::Result<Volume> load_dicom_path(const std::filesystem::path& path,
                                     const LoadOptions& options) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) {
        return base::make_error(base::ErrorCode::not_found, "file or folder not found",
                                detail::at_file(path));
    }
    prepare_library();
    if (!dcmDataDict.isDictionaryLoaded()) {
        return base::make_error(base::ErrorCode::dicom_unavailable,
                                "DCMTK found no DICOM data dictionary (install libdcmtk17 or set "
                                "DCMDICTPATH)",
                                detail::at_file(path));
    }
    if (std::filesystem::is_directory(status)) {
        return load_dicom_folder(path, options);
    }
    return load_dicom_file(path, options);
}

}  // namespace
}  // namespace detail::dicom

base::Result<std::vector<DicomSeries>> list_dicom_series(const std::filesystem::path& folder,
                                                         bool subfolders) {
    detail::dicom::prepare_library();
    auto found = detail::dicom::read_folder(folder, subfolders, false);
    if (!found) {
        return found.error();
    }
    return detail::dicom::series_of(found->images);
}

base::Result<Volume> load_dicom(const std::filesystem::path& path, const LoadOptions& options) {
    return detail::guard_allocation(path,
                                    [&] { return detail::dicom::load_dicom_path(path, options); });
}

}  // namespace penumbra::volume
