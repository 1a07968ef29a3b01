#pragma once

// Siemens mosaics: the slices of a volume tiled in one stored image, their count and direction
// kept in Siemens' private CSA header. Unpacked here so that a mosaic series opens like any other
// while the untrusted binary CSA header is parsed in one place only. Private to the volume module.

#include "dicom_image.hpp"

#include <penumbra/base/result.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include <dcmtk/config/osconfig.h>  // must come before the other DCMTK headers
#include <dcmtk/dcmdata/dcdatset.h>

namespace penumbra::volume::detail::dicom {

// A Siemens mosaic tiles every slice of a volume in one image, ceil(sqrt(n)) tiles a side, row by
// row: unpacked into its n slices, whose positions sit along the CSA header's slice normal (see
// read_frames). Refused, saying "mosaic", where the number of slices is missing or does not tile
// the image.
base::Result<std::optional<Mosaic>> read_mosaic(DcmDataset& dataset, PixelFormat& format,
                                                std::uint32_t& frame_count,
                                                const std::filesystem::path& path);

// The positions of a mosaic's slices. Its ImagePositionPatient is that of the tiled image's
// first pixel as if it were one slice: the first tile's first pixel lies half the difference of
// the two sizes further along the rows and columns (the correction nibabel and dcm2niix make);
// each next slice steps along the CSA slice normal (else the row x column direction) by
// SpacingBetweenSlices, else SliceThickness. Without position or orientation the slices keep
// their tile order.
void place_mosaic_slices(std::vector<Frame>& frames, const Mosaic& mosaic, const PixelFormat& tile);

}  // namespace penumbra::volume::detail::dicom
