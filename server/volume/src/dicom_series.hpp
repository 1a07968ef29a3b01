#pragma once

// The series of a folder's images: grouped by SeriesInstanceUID, listed for a user to choose from
// (a listing reads headers only), and the chosen one kept for a load. Private to the volume
// module.

#include "dicom_image.hpp"

#include <penumbra/base/result.hpp>
#include <penumbra/volume/volume.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace penumbra::volume::detail::dicom {

// The series of the images, ordered by SeriesNumber (numerically), then UID.
std::vector<DicomSeries> series_of(const std::vector<Image>& images);

// Keeps the images of the series `wanted` names (its number or UID), or of the only series.
base::Result<DicomSeries> select_series(std::vector<Image>& images, const std::string& wanted,
                                        const std::filesystem::path& folder);

}  // namespace penumbra::volume::detail::dicom
