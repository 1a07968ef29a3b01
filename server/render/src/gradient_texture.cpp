#include "gradient_texture.hpp"

#include <penumbra/gpu/commands.hpp>

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
    const glm::ivec3 size(dims);
    gpu::Texture gradients = gpu::create_texture_3d(GL_RGBA16F, size.x, size.y, size.z);
    if (gpu::take_error() == GL_OUT_OF_MEMORY) {
        return base::make_error(base::ErrorCode::gpu_out_of_memory,
                                "not enough GPU memory for the gradients", "gradients");
    }
    gpu::set_sampling(gradients, GL_LINEAR, GL_CLAMP_TO_EDGE);
    gpu::bind_texture(0, volume.texture);
    gpu::bind_image(0, gradients, GL_WRITE_ONLY, GL_RGBA16F);
    gpu::set_uniform(**program, 0, volume.value_map.x, volume.value_map.y);
    gpu::dispatch(**program, gpu::groups_covering(4, size.x, size.y, size.z),
                  GL_TEXTURE_FETCH_BARRIER_BIT);
    return gradients;
}

}  // namespace penumbra::render
