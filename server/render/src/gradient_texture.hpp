#pragma once

#include "program_cache.hpp"
#include "volume_texture.hpp"

#include <penumbra/base/result.hpp>
#include <penumbra/gpu/objects.hpp>

#include <glm/vec3.hpp>

namespace penumbra::render {

// The per-voxel central differences of a volume (shaders/gradient_build.comp), RGBA16F, filtered
// linearly like the volume: what shaders/include/gradient.glsl reads with GRADIENT_TEXTURE=1.
base::Result<gpu::Texture> build_gradient_texture(ProgramCache& programs,
                                                  const VolumeTexture& volume, glm::uvec3 dims);

// Bytes a gradient texture of `dims` voxels holds.
std::size_t gradient_texture_bytes(glm::uvec3 dims);

}  // namespace penumbra::render
