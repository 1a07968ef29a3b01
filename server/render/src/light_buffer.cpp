#include "light_buffer.hpp"

#include "frame_target.hpp"

#include <algorithm>

namespace penumbra::render {

LightBuffer::LightBuffer(int slices, int resolution)
    : layers_(gpu::create_texture(GL_TEXTURE_2D_ARRAY))
    , slices_(slices)
    , resolution_(resolution) {
    glTextureStorage3D(layers_.name(), 1, GL_R16F, resolution, resolution, slices);
    glTextureParameteri(layers_.name(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(layers_.name(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(layers_.name(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(layers_.name(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

std::vector<float> LightBuffer::read() const {
    std::vector<float> values(static_cast<std::size_t>(resolution_) * resolution_ * slices_);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureImage(layers_.name(), 0, GL_RED, GL_FLOAT,
                      static_cast<GLsizei>(values.size() * sizeof(float)), values.data());
    return values;
}

base::ImageRgba8 LightBuffer::layer_image(int layer) const {
    std::vector<float> values(static_cast<std::size_t>(resolution_) * resolution_);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureSubImage(layers_.name(), 0, 0, 0, layer, resolution_, resolution_, 1, GL_RED,
                         GL_FLOAT, static_cast<GLsizei>(values.size() * sizeof(float)),
                         values.data());
    return transmittance_image(values, resolution_);
}

LightBufferBuilder::LightBufferBuilder(ProgramCache& programs)
    : programs_(programs) {}

base::Status LightBufferBuilder::build(LightBuffer& target, scene::LightBufferBuilder builder,
                                       const SliceMesh& mesh, const gpu::Defines& defines,
                                       int slab_samples, gpu::GpuTimer& timer, WorkChunks& chunks) {
    const bool per_slice = builder == scene::LightBufferBuilder::per_slice;
    auto built = per_slice ? programs_.graphics("light_buffer_slice.vert",
                                                "light_buffer_slice.frag", defines)
                           : programs_.compute("light_buffer.comp", defines);
    if (!built) {
        return built.error();
    }
    const double texel_work = std::max(1, slab_samples);
    const double layer_texels = double(target.resolution()) * target.resolution();
    timer.begin();
    base::Status status =
            per_slice ? build_per_slice(target, mesh, **built, layer_texels * texel_work, chunks)
                      : build_multi_slice(target, **built, target.slices() * texel_work, chunks);
    timer.end();
    return status;
}

// Builder B in tiles of texels, each dispatch marching its texels through every slice.
base::Status LightBufferBuilder::build_multi_slice(LightBuffer& target, const gpu::Program& program,
                                                   double work_per_texel, WorkChunks& chunks) {
    const float one = 1.0f;
    glClearTexImage(target.texture(), 0, GL_RED, GL_FLOAT, &one);
    glUseProgram(program.name());
    glBindImageTexture(0, target.texture(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_R16F);
    const int resolution = target.resolution();
    const Tile tile = tile_of(chunks.work_per_chunk() / work_per_texel, resolution, resolution);
    for (int y = 0; y < resolution; y += tile.height) {
        for (int x = 0; x < resolution; x += tile.width) {
            glUniform2i(0, x, y);
            glDispatchCompute(static_cast<GLuint>(tile.width / group_side),
                              static_cast<GLuint>(tile.height / group_side), 1);
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
            if (!chunks.continue_after_chunk()) {
                return cancelled_error();
            }
        }
    }
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    return base::Ok{};
}

// The paper's builder: the framebuffer holds the transmittance so far; each slice is blended in
// multiplicatively and the result copied into the next layer. Cut into groups of slices.
base::Status LightBufferBuilder::build_per_slice(LightBuffer& target, const SliceMesh& mesh,
                                                 const gpu::Program& program, double work_per_slice,
                                                 WorkChunks& chunks) {
    const int resolution = target.resolution();
    if (!scratch_ || scratch_resolution_ != resolution) {
        scratch_ = gpu::create_texture(GL_TEXTURE_2D);
        glTextureStorage2D(scratch_.name(), 1, GL_R16F, resolution, resolution);
        scratch_framebuffer_ = gpu::create_framebuffer();
        glNamedFramebufferTexture(scratch_framebuffer_.name(), GL_COLOR_ATTACHMENT0,
                                  scratch_.name(), 0);
        scratch_resolution_ = resolution;
    }
    if (glCheckNamedFramebufferStatus(scratch_framebuffer_.name(), GL_FRAMEBUFFER) !=
        GL_FRAMEBUFFER_COMPLETE) {
        return base::make_error("gl_error", "the light-buffer framebuffer is incomplete",
                                "light_buffer");
    }
    const int slices_per_chunk = static_cast<int>(
            std::clamp(chunks.work_per_chunk() / work_per_slice, 1.0, double(target.slices())));
    glBindFramebuffer(GL_FRAMEBUFFER, scratch_framebuffer_.name());
    glViewport(0, 0, resolution, resolution);
    const float one[4] = {1.0f, 1.0f, 1.0f, 1.0f};
    glClearNamedFramebufferfv(scratch_framebuffer_.name(), GL_COLOR, 0, one);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ZERO, GL_SRC_COLOR);
    glUseProgram(program.name());
    mesh.bind();
    base::Status status = base::Ok{};
    for (int k = 0; k < target.slices(); ++k) {
        glCopyImageSubData(scratch_.name(), GL_TEXTURE_2D, 0, 0, 0, 0, target.texture(),
                           GL_TEXTURE_2D_ARRAY, 0, 0, 0, k, resolution, resolution, 1);
        if (k + 1 < target.slices()) {
            mesh.draw(k);
        }
        if ((k + 1) % slices_per_chunk == 0 && k + 1 < target.slices() &&
            !chunks.continue_after_chunk()) {
            status = cancelled_error();
            break;
        }
    }
    glDisable(GL_BLEND);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return status;
}

}  // namespace penumbra::render
