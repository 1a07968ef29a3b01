#pragma once

// The DICOM images of a folder: which files a search takes and what it passes over, so that a
// load or a listing can open the series it finds and say what it left out. Private to the volume
// module.

#include "dicom_image.hpp"

#include <penumbra/base/result.hpp>

#include <array>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::volume::detail::dicom {

// The image headers of a folder, with what was passed over.
struct FolderImages {
    std::vector<Image> images;
    std::vector<std::filesystem::path> not_dicom;
    std::size_t not_images = 0;
    std::optional<base::Error> other_kind;  // the first image of a kind a volume cannot hold

    // Files with the DICOM marker that cannot be read as an image (cut short, damaged headers),
    // in path order: each one's error, and what of its header was read before the damage.
    struct Damaged {
        base::Error error;
        std::string series_uid;
        std::optional<std::array<double, 3>> position;  // ImagePositionPatient (LPS)
    };

    std::vector<Damaged> damaged;

    // What a volume of the folder says about the files it passed over, one line each: every
    // damaged file (the volume lacks whatever slices it held), and the files that are not DICOM.
    [[nodiscard]] std::vector<std::string> notes() const;
    // " (skipped as damaged: a, b)" where files were skipped, else empty: the likely cause of a
    // gap in the series.
    [[nodiscard]] std::string damaged_suffix() const;
};

// `keep_files`: keep each image's parsed file for its pixel data (a load), or drop it once its
// header is read (a listing of a folder's series, which may hold thousands of files).
base::Result<FolderImages> read_folder(const std::filesystem::path& folder, bool subfolders,
                                       bool keep_files);

}  // namespace penumbra::volume::detail::dicom
