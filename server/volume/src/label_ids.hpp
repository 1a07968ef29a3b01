#pragma once

#include <penumbra/volume/volume.hpp>

#include <cstddef>
#include <cstdint>

namespace penumbra::volume {

// The label id voxel `index` of an integer volume holds: its stored value through the rescale,
// rounded (a label map's ids are whole numbers).
[[nodiscard]] std::int64_t label_id_of_voxel(const Volume& volume, std::size_t index);

}  // namespace penumbra::volume
