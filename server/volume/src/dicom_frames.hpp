#pragma once

// The frames of a series in space: where each lies (functional groups or top-level tags), their
// order along the slice normal, the spacing between them, and the patient geometry they give a
// volume. Private to the volume module.

#include "dicom_image.hpp"

#include <penumbra/base/result.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <dcmtk/config/osconfig.h>  // must come before the other DCMTK headers
#include <dcmtk/dcmdata/dcdatset.h>

namespace penumbra::volume::detail::dicom {

// Slice gaps may differ from the median gap by this fraction: scanners write positions
// rounded to a few decimals, while a missing slice changes a gap by 100 %.
inline constexpr double gap_tolerance = 0.01;

// Positions this close along the normal are one position repeated, not two slices: scanners
// write them to a micrometre or finer, and no series has slices that close.
inline constexpr double same_position = 1e-3;  // mm

// A distance along the slice normal as messages write it: "3 mm".
std::string millimetres(double value);

// ImageOrientationPatient's row x column direction (not normalised).
glm::dvec3 slice_normal(const std::array<double, 6>& orientation);

// The frames of image `image_index` (of `frame_count` frames, `format` a frame), with what their
// headers say of position, spacing and rescale; a mosaic's slices are placed along its normal.
std::vector<Frame> read_frames(DcmDataset& dataset, std::size_t image_index,
                               std::uint32_t frame_count, const std::optional<Mosaic>& mosaic,
                               const PixelFormat& format);

// Sorts the frames into z order and returns the spacing between them; of a series holding
// several volumes, keeps the first and says so in `notes`.
base::Result<double> order_frames(std::vector<Frame>& frames, const std::vector<Image>& images,
                                  const std::filesystem::path& source,
                                  std::vector<std::string>& notes);

// PixelSpacing (x, y), the same for every frame; 1 mm with a warning where it is missing.
base::Result<glm::dvec2> pixel_spacing(const std::vector<Frame>& frames,
                                       const std::vector<Image>& images,
                                       const std::filesystem::path& source);

// Where the ordered frames lie in patient space, in RAS: i along a row (ImageOrientationPatient's
// first direction), j down a column (its second), k from the first frame to the next (the
// positions' mean step, which for a gantry-tilted series leans off the normal and is refused as
// sheared). Without positions k is the slice normal; without orientation the axes are identity.
// DICOM's patient space is LPS, so x and y are negated.
base::Result<Geometry> patient_geometry(const std::vector<Frame>& frames, glm::dvec2 xy_spacing,
                                        double z_spacing, const std::vector<Image>& images);

}  // namespace penumbra::volume::detail::dicom
