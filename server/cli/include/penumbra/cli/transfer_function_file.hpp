#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/scene/transfer_function.hpp>
#include <penumbra/volume/volume.hpp>

#include <string>

namespace penumbra::cli {

// A preset name, or a path to a JSON file in the protocol's transfer-function shape
// (proto/README.md): positions "normalized" to the value range, or "data" values.
base::Result<scene::TransferFunction> load_transfer_function(const std::string& preset_or_path,
                                                             const volume::ValueRange& range);

}  // namespace penumbra::cli
