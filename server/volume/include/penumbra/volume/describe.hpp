#pragma once

// A volume described in text for people: what `penumbra info` prints.

#include <penumbra/volume/volume.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace penumbra::volume {

// Name and `source` (the path it was opened from), dimensions, spacing, extent, orientation, the
// index-to-patient transform, voxel type, rescale, range, the loader's notes and the voxels it
// replaced: one "label: value" line each, each line ending in '\n'.
[[nodiscard]] std::string describe(const Volume& volume, const std::string& source);

// The distribution of its values: `bins` (at least one) equal-width bins, one line each with the
// bin's lower edge, its count and a bar proportional to the fullest bin.
[[nodiscard]] std::string describe_histogram(const Volume& volume, std::size_t bins = 16);

// The series of a DICOM folder, as list_dicom_series gives them: a table of number, modality,
// slices, description and UID under a heading line.
[[nodiscard]] std::string describe_series(const std::vector<DicomSeries>& series);

}  // namespace penumbra::volume
