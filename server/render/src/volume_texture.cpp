#include "volume_texture.hpp"

#include <string>
#include <vector>

namespace penumbra::render {

base::Result<VolumeTexture> upload_volume(const volume::Volume& volume, int max_3d_texture_size) {
    const glm::uvec3 dims = volume.dims;
    const auto limit = static_cast<unsigned>(max_3d_texture_size);
    if (dims.x > limit || dims.y > limit || dims.z > limit) {
        return base::make_error("volume_too_large",
                                "volume " + std::to_string(dims.x) + "x" + std::to_string(dims.y) +
                                        "x" + std::to_string(dims.z) +
                                        " exceeds this GPU's 3D texture limit of " +
                                        std::to_string(max_3d_texture_size) + " per side",
                                volume.name);
    }
    GLenum internal_format = GL_R8;
    GLenum type = GL_UNSIGNED_BYTE;
    double texel_max = 1.0;  // what a normalised texel of 1.0 stands for in voxel values
    switch (volume.type) {
        case volume::VoxelType::uint8: texel_max = 255.0; break;
        case volume::VoxelType::uint16:
            internal_format = GL_R16;
            type = GL_UNSIGNED_SHORT;
            texel_max = 65535.0;
            break;
        case volume::VoxelType::float32:
            internal_format = GL_R32F;
            type = GL_FLOAT;
            break;
    }
    const double width = volume.range.max - volume.range.min;
    // Float volumes are stored already mapped to [0, 1]: a range near ±3e38 makes 1/width a
    // denormal that shaders flush to zero, and at a huge offset the raw floats are too coarse.
    std::vector<float> normalized;
    const void* pixels = volume.data.data();
    if (volume.type == volume::VoxelType::float32) {
        normalized.resize(volume.voxel_count());
        const auto* raw = reinterpret_cast<const float*>(volume.data.data());
        for (std::size_t i = 0; i < normalized.size(); ++i) {
            normalized[i] = width > 0.0 ? static_cast<float>(
                                                  (static_cast<double>(raw[i]) - volume.range.min) /
                                                  width)
                                        : 0.0f;
        }
        pixels = normalized.data();
    }
    VolumeTexture out;
    out.texture = gpu::create_texture(GL_TEXTURE_3D);
    const GLuint name = out.texture.name();
    glTextureStorage3D(name, 1, internal_format, static_cast<GLsizei>(dims.x),
                       static_cast<GLsizei>(dims.y), static_cast<GLsizei>(dims.z));
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage3D(name, 0, 0, 0, 0, static_cast<GLsizei>(dims.x),
                        static_cast<GLsizei>(dims.y), static_cast<GLsizei>(dims.z), GL_RED, type,
                        pixels);
    glTextureParameteri(name, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(name, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(name, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(name, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureParameteri(name, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    if (glGetError() == GL_OUT_OF_MEMORY) {
        return base::make_error("gpu_out_of_memory", "not enough GPU memory for the volume",
                                volume.name);
    }
    if (volume.type == volume::VoxelType::float32) {
        out.value_map = glm::vec2(1.0f, 0.0f);
    } else if (width > 0.0) {
        out.value_map = glm::vec2(static_cast<float>(texel_max / width),
                                  static_cast<float>(-volume.range.min / width));
    } else {
        out.value_map = glm::vec2(0.0f, 0.0f);  // a constant volume classifies as value 0
    }
    return out;
}

}  // namespace penumbra::render
