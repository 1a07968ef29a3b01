#include "volume_texture.hpp"

#include <string>

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
    VolumeTexture out;
    out.texture = gpu::create_texture(GL_TEXTURE_3D);
    const GLuint name = out.texture.name();
    glTextureStorage3D(name, 1, internal_format, static_cast<GLsizei>(dims.x),
                       static_cast<GLsizei>(dims.y), static_cast<GLsizei>(dims.z));
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage3D(name, 0, 0, 0, 0, static_cast<GLsizei>(dims.x),
                        static_cast<GLsizei>(dims.y), static_cast<GLsizei>(dims.z), GL_RED, type,
                        volume.data.data());
    glTextureParameteri(name, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(name, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(name, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(name, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureParameteri(name, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    if (glGetError() == GL_OUT_OF_MEMORY) {
        return base::make_error("gpu_out_of_memory", "not enough GPU memory for the volume",
                                volume.name);
    }
    const double width = volume.range.max - volume.range.min;
    if (width > 0.0) {
        out.value_map = glm::vec2(static_cast<float>(texel_max / width),
                                  static_cast<float>(-volume.range.min / width));
    } else {
        out.value_map = glm::vec2(0.0f, 0.0f);  // a constant volume classifies as value 0
    }
    return out;
}

}  // namespace penumbra::render
