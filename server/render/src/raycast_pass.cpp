#include "raycast_pass.hpp"

namespace penumbra::render {

gpu::Defines RaycastVariant::defines() const {
    return {{"SHADOWS", std::to_string(static_cast<int>(shadows))},
            {"SCATTERING", std::to_string(static_cast<int>(scattering))},
            {"PHONG", phong ? "1" : "0"},
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
    , empty_vertex_array_(gpu::create_vertex_array()) {}

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

base::Status RaycastPass::run(const RaycastVariant& variant, int width, int height,
                              FrameTarget& target, gpu::GpuTimer& timer) {
    auto program = program_for(variant);
    if (!program) {
        return program.error();
    }
    target.ensure(width, height);
    glUseProgram((*program)->name());
    timer.begin();
    if (variant.stage == scene::RaycastStage::compute) {
        glBindImageTexture(0, target.texture(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
        glDispatchCompute(static_cast<GLuint>((width + 7) / 8),
                          static_cast<GLuint>((height + 7) / 8), 1);
        glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    } else {
        glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer());
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

}  // namespace penumbra::render
