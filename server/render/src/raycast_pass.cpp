#include "raycast_pass.hpp"

namespace penumbra::render {

gpu::Defines RaycastVariant::defines() const {
    return {{"PHONG", phong ? "1" : "0"},
            {"EXTINCTION", extinction ? "1" : "0"},
            {"POINT_LIGHT", point_light ? "1" : "0"}};
}

std::string RaycastVariant::key() const {
    std::string text;
    for (const auto& [name, value] : defines()) {
        text += name + "=" + value + " ";
    }
    return text + scene::to_string(stage);
}

RaycastPass::RaycastPass(const gpu::ShaderLibrary& shaders)
    : shaders_(shaders)
    , uniform_buffer_(gpu::create_buffer())
    , empty_vertex_array_(gpu::create_vertex_array()) {
    glNamedBufferStorage(uniform_buffer_.name(), sizeof(FrameUniforms), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
}

base::Result<const gpu::Program*> RaycastPass::program_for(const RaycastVariant& variant) {
    const std::string key = variant.key();
    if (auto found = programs_.find(key); found != programs_.end()) {
        return &found->second;
    }
    auto program = variant.stage == scene::RaycastStage::compute
                           ? shaders_.build_compute("raycast.comp", variant.defines())
                           : shaders_.build_graphics("fullscreen.vert", "raycast.frag",
                                                     variant.defines());
    if (!program) {
        return program.error();
    }
    return &programs_.emplace(key, std::move(program.value())).first->second;
}

void RaycastPass::ensure_target(int width, int height) {
    if (target_ && width == width_ && height == height_) {
        return;
    }
    target_ = gpu::create_texture(GL_TEXTURE_2D);
    glTextureStorage2D(target_.name(), 1, GL_RGBA8, width, height);
    framebuffer_ = gpu::create_framebuffer();
    glNamedFramebufferTexture(framebuffer_.name(), GL_COLOR_ATTACHMENT0, target_.name(), 0);
    width_ = width;
    height_ = height;
}

base::Status RaycastPass::run(const RaycastVariant& variant, const FrameUniforms& uniforms,
                              gpu::GpuTimer& timer) {
    auto program = program_for(variant);
    if (!program) {
        return program.error();
    }
    const int width = uniforms.image_size.x;
    const int height = uniforms.image_size.y;
    ensure_target(width, height);
    glNamedBufferSubData(uniform_buffer_.name(), 0, sizeof(FrameUniforms), &uniforms);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, uniform_buffer_.name());
    glUseProgram((*program)->name());
    timer.begin();
    if (variant.stage == scene::RaycastStage::compute) {
        glBindImageTexture(0, target_.name(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
        glDispatchCompute(static_cast<GLuint>((width + 7) / 8),
                          static_cast<GLuint>((height + 7) / 8), 1);
        glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    } else {
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.name());
        glViewport(0, 0, width, height);
        glDisable(GL_BLEND);
        glDisable(GL_DEPTH_TEST);
        glBindVertexArray(empty_vertex_array_.name());
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    timer.end();
    return base::Ok{};
}

void RaycastPass::read_back(base::ImageRgba8& image) const {
    image = base::ImageRgba8(width_, height_);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(target_.name(), 0, GL_RGBA, GL_UNSIGNED_BYTE,
                      static_cast<GLsizei>(image.pixels.size()), image.pixels.data());
}

}  // namespace penumbra::render
