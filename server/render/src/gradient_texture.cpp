#include "gradient_texture.hpp"

namespace penumbra::render {

std::size_t gradient_texture_bytes(glm::uvec3 dims) {
    return std::size_t{8} * dims.x * dims.y * dims.z;  // four half floats per voxel
}

base::Result<gpu::Texture> build_gradient_texture(ProgramCache& programs,
                                                  const VolumeTexture& volume, glm::uvec3 dims) {
    auto program = programs.compute("gradient_build.comp");
    if (!program) {
        return program.error();
    }
    gpu::Texture gradients = gpu::create_texture(GL_TEXTURE_3D);
    const GLuint name = gradients.name();
    glTextureStorage3D(name, 1, GL_RGBA16F, static_cast<GLsizei>(dims.x),
                       static_cast<GLsizei>(dims.y), static_cast<GLsizei>(dims.z));
    if (glGetError() == GL_OUT_OF_MEMORY) {
        return base::make_error("gpu_out_of_memory", "not enough GPU memory for the gradients",
                                "gradients");
    }
    glTextureParameteri(name, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(name, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(name, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(name, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureParameteri(name, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    glUseProgram((*program)->name());
    glBindTextureUnit(0, volume.texture.name());
    glBindImageTexture(0, name, 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    glUniform2f(0, volume.value_map.x, volume.value_map.y);
    const auto groups = [](unsigned voxels) { return static_cast<GLuint>((voxels + 3) / 4); };
    glDispatchCompute(groups(dims.x), groups(dims.y), groups(dims.z));
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    return gradients;
}

}  // namespace penumbra::render
