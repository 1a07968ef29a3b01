#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/vec2.hpp>

namespace penumbra::render {

// A volume on the GPU: uint8 → R8, uint16 → R16, int16 → R16 offset by 32768 (all normalised,
// every value exact), float32 → R32F already mapped to [0, 1]. `value_map` turns a texel into the
// volume's real values (its rescale applied) mapped to [0, 1] over its range: texel * x + y.
struct VolumeTexture {
    gpu::Texture texture;
    glm::vec2 value_map{1.0f, 0.0f};
};

base::Result<VolumeTexture> upload_volume(const volume::Volume& volume, int max_3d_texture_size);

}  // namespace penumbra::render
