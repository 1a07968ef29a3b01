#include "volume_texture.hpp"

#include <penumbra/gpu/commands.hpp>

#include <glm/vec3.hpp>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace penumbra::render {

base::Result<VolumeTexture> upload_volume(const volume::Volume& volume, int max_3d_texture_size) {
    const glm::uvec3 dims = volume.dims;
    const auto limit = static_cast<unsigned>(max_3d_texture_size);
    if (dims.x > limit || dims.y > limit || dims.z > limit) {
        return base::make_error(base::ErrorCode::volume_too_large,
                                "volume " + std::to_string(dims.x) + "x" + std::to_string(dims.y) +
                                        "x" + std::to_string(dims.z) +
                                        " exceeds this GPU's 3D texture limit of " +
                                        std::to_string(max_3d_texture_size) + " per side",
                                volume.name);
    }
    // Integer volumes go up as normalised unsigned texels (exact: 8 or 16 bits for 8- or 16-bit
    // values; int16 offset by 32768 into uint16, as R16_SNORM would merge -32768 with -32767).
    // A texel of t stands for the stored value t * texel_max + texel_offset.
    GLenum internal_format = GL_R8;
    GLenum type = GL_UNSIGNED_BYTE;
    double texel_max = 1.0;
    double texel_offset = 0.0;
    const void* pixels = volume.data.data();
    std::vector<std::uint16_t> offset_int16;
    std::vector<float> normalized;
    const double width = volume.range.max - volume.range.min;
    switch (volume.type) {
        case volume::VoxelType::uint8:
            texel_max = 255.0;
            break;
        case volume::VoxelType::uint16:
            internal_format = GL_R16;
            type = GL_UNSIGNED_SHORT;
            texel_max = 65535.0;
            break;
        case volume::VoxelType::int16: {
            internal_format = GL_R16;
            type = GL_UNSIGNED_SHORT;
            texel_max = 65535.0;
            texel_offset = -32768.0;
            offset_int16.resize(volume.voxel_count());
            for (std::size_t i = 0; i < offset_int16.size(); ++i) {
                std::int16_t value = 0;
                std::memcpy(&value, volume.data.data() + i * sizeof value, sizeof value);
                offset_int16[i] = static_cast<std::uint16_t>(std::int32_t{value} + 32768);
            }
            pixels = offset_int16.data();
            break;
        }
        case volume::VoxelType::float32: {
            // Float volumes are stored already mapped to [0, 1]: a range near ±3e38 makes
            // 1/width a denormal that shaders flush to zero, and at a huge offset the raw floats
            // are too coarse.
            internal_format = GL_R32F;
            type = GL_FLOAT;
            normalized.resize(volume.voxel_count());
            const auto* raw = reinterpret_cast<const float*>(volume.data.data());
            for (std::size_t i = 0; i < normalized.size(); ++i) {
                const double real = volume.rescale.apply(static_cast<double>(raw[i]));
                normalized[i] =
                        width > 0.0 ? static_cast<float>((real - volume.range.min) / width) : 0.0f;
            }
            pixels = normalized.data();
            break;
        }
    }
    VolumeTexture out;
    const glm::ivec3 size(dims);
    out.texture = gpu::create_texture_3d(internal_format, size.x, size.y, size.z);
    gpu::upload_3d(out.texture, size.x, size.y, size.z, GL_RED, type, pixels);
    gpu::set_sampling(out.texture, GL_LINEAR, GL_CLAMP_TO_EDGE);
    if (gpu::take_error() == GL_OUT_OF_MEMORY) {
        return base::make_error(base::ErrorCode::gpu_out_of_memory,
                                "not enough GPU memory for the volume", volume.name);
    }
    if (volume.type == volume::VoxelType::float32) {
        out.value_map = glm::vec2(1.0f, 0.0f);
    } else if (width > 0.0) {
        // real = (t * texel_max + texel_offset) * slope + intercept, then mapped to [0, 1].
        const volume::Rescale& rescale = volume.rescale;
        out.value_map = glm::vec2(
                static_cast<float>(texel_max * rescale.slope / width),
                static_cast<float>((rescale.apply(texel_offset) - volume.range.min) / width));
    } else {
        out.value_map = glm::vec2(0.0f, 0.0f);  // a constant volume classifies as value 0
    }
    return out;
}

}  // namespace penumbra::render
