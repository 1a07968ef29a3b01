#include "raycast_pass.hpp"

#include <algorithm>

namespace penumbra::render {

gpu::Defines RaycastVariant::defines() const {
    return {{"SHADOWS", std::to_string(static_cast<int>(shadows))},
            {"SCATTERING", std::to_string(static_cast<int>(scattering))},
            {"PHONG", phong ? "1" : "0"},
            {"EXTINCTION", extinction ? "1" : "0"},
            {"POINT_LIGHT", point_light ? "1" : "0"},
            {"LOCAL_LIGHT_LOOKUP", local_light_lookup ? "1" : "0"},
            {"CHUNKED", chunked ? "1" : "0"}};
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

base::Result<const gpu::Program*> RaycastPass::resolve_program() {
    if (auto found = programs_.find("resolve"); found != programs_.end()) {
        return &found->second;
    }
    auto program = shaders_.build_compute("resolve.comp", {});
    if (!program) {
        return program.error();
    }
    return &programs_.emplace("resolve", std::move(program.value())).first->second;
}

base::Result<int> RaycastPass::run(RaycastVariant variant, int width, int height,
                                   const MarchBudget& budget, FrameTarget& target,
                                   gpu::GpuTimer& timer) {
    // A safety margin under the cap covers the few iterations outside the march loop.
    const long long cap = budget.loop_cap > 0 ? budget.loop_cap - 1000 : 0;
    const long long needed =
            static_cast<long long>(budget.max_samples_per_ray) * budget.iterations_per_sample;
    if (cap > 0 && needed > cap) {
        if (variant.stage == scene::RaycastStage::fragment) {
            return base::make_error("unsupported_settings",
                                    "this GL implementation stops a fragment shader after " +
                                            std::to_string(budget.loop_cap) +
                                            " loop iterations, fewer than these rays need; use "
                                            "the compute stage, which marches them in chunks",
                                    "stage");
        }
        variant.chunked = true;
    }
    target.ensure(width, height);
    const auto groups_x = static_cast<GLuint>((width + 7) / 8);
    const auto groups_y = static_cast<GLuint>((height + 7) / 8);
    if (variant.chunked) {
        auto program = program_for(variant);
        auto resolve = resolve_program();
        if (!program || !resolve) {
            return !program ? program.error() : resolve.error();
        }
        if (!accumulation_ || accumulation_width_ != width || accumulation_height_ != height) {
            accumulation_ = gpu::create_texture(GL_TEXTURE_2D);
            glTextureStorage2D(accumulation_.name(), 1, GL_RGBA32F, width, height);
            accumulation_width_ = width;
            accumulation_height_ = height;
        }
        const int per_dispatch =
                static_cast<int>(std::max<long long>(1, cap / budget.iterations_per_sample));
        const int dispatches = (budget.max_samples_per_ray + per_dispatch - 1) / per_dispatch;
        timer.begin();
        glUseProgram((*program)->name());
        glBindImageTexture(1, accumulation_.name(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
        glUniform1i(1, per_dispatch);
        for (int d = 0; d < dispatches; ++d) {
            glUniform1i(0, d * per_dispatch);
            glDispatchCompute(groups_x, groups_y, 1);
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        }
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        glUseProgram((*resolve)->name());
        glBindTextureUnit(0, accumulation_.name());
        glBindImageTexture(0, target.texture(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
        glDispatchCompute(groups_x, groups_y, 1);
        glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
        timer.end();
        return dispatches;
    }
    auto program = program_for(variant);
    if (!program) {
        return program.error();
    }
    glUseProgram((*program)->name());
    timer.begin();
    if (variant.stage == scene::RaycastStage::compute) {
        glBindImageTexture(0, target.texture(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
        glDispatchCompute(groups_x, groups_y, 1);
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
    return 1;
}

}  // namespace penumbra::render
