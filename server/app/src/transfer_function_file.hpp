#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/scene/transfer_function.hpp>
#include <penumbra/volume/volume.hpp>

#include <filesystem>
#include <string>

namespace penumbra::app {

// Reads a transfer function from JSON:
//   { "name": "bone", "space": "normalized" | "data",
//     "colors":    [ { "x": 0.3, "rgb": [0.9, 0.8, 0.7] }, ... ],
//     "opacities": [ { "x": 0.3, "alpha": 0.0 }, ... ] }
// With "space": "data", positions are voxel values and are mapped into the volume's range.
base::Result<scene::TransferFunction> parse_transfer_function_json(const std::string& text,
                                                                   const volume::ValueRange& range,
                                                                   const std::string& where);

// A preset name or a path to a JSON file.
base::Result<scene::TransferFunction> load_transfer_function(const std::string& preset_or_path,
                                                             const volume::ValueRange& range);

}  // namespace penumbra::app
