#pragma once

// A chosen series' images made into a Volume: its frames ordered and placed, each image's pixel
// data read and decoded once, into the narrowest voxel type that keeps the stored values. Private
// to the volume module.

#include "dicom_image.hpp"

#include <penumbra/base/result.hpp>
#include <penumbra/volume/volume.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace penumbra::volume::detail::dicom {

// Refused where the images disagree in pixel format, or exceed the limits or the memory budget of
// `options`; each image's parsed file is dropped once its pixels are decoded. `source` is the file
// or folder that errors name.
base::Result<Volume> assemble(std::vector<Image>& images, const std::string& name,
                              const std::filesystem::path& source, const LoadOptions& options);

}  // namespace penumbra::volume::detail::dicom
