#include "raycast_pass.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra::render {

gpu::Defines RaycastVariant::defines() const {
    return {{"SHADOWS", std::to_string(static_cast<int>(shadows))},
            {"SCATTERING", std::to_string(static_cast<int>(scattering))},
            {"PHONG", phong ? "1" : "0"},
            {"EXTINCTION", extinction ? "1" : "0"},
            {"POINT_LIGHT", point_light ? "1" : "0"},
            {"LOCAL_LIGHT_LOOKUP", local_light_lookup ? "1" : "0"},
            {"EMPTY_SPACE_SKIPPING", empty_space_skipping ? "1" : "0"},
            {"GRADIENT_TEXTURE", gradient_texture ? "1" : "0"},
            {"CHUNKED", chunked ? "1" : "0"}};
}

std::string RaycastVariant::key() const {
    std::string text;
    for (const auto& [name, value] : defines()) {
        text += name + "=" + value + " ";
    }
    return text + scene::to_string(stage);
}

RaycastPass::RaycastPass(ProgramCache& programs)
    : programs_(programs)
    , empty_vertex_array_(gpu::create_vertex_array()) {}

base::Result<const gpu::Program*> RaycastPass::program_for(const RaycastVariant& variant) {
    return variant.stage == scene::RaycastStage::compute
                   ? programs_.compute("raycast.comp", variant.defines())
                   : programs_.graphics("fullscreen.vert", "raycast.frag", variant.defines());
}

namespace {

int round_up_to_groups(int pixels) {
    return (pixels + group_side - 1) / group_side * group_side;
}

// The cap less a safety margin for the few iterations outside the march loop; 0: no cap.
long long usable_loop_cap(const MarchBudget& budget) {
    return budget.loop_cap > 0 ? budget.loop_cap - 1000 : 0;
}

}  // namespace

MarchChunks plan_march_chunks(const MarchBudget& budget, int width, int height,
                              double work_per_chunk, bool split_steps) {
    const int per_sample = std::max(1, budget.iterations_per_sample);
    const double work =
            work_per_chunk > 0.0 ? work_per_chunk : std::numeric_limits<double>::infinity();
    int steps = budget.max_samples_per_ray;
    if (split_steps) {
        if (const long long cap = usable_loop_cap(budget); cap > 0) {
            steps = static_cast<int>(std::min<long long>(steps, std::max(1LL, cap / per_sample)));
        }
        // A chunk holds at least one work group's rays.
        const double group_steps = work / (group_side * group_side * double(per_sample));
        steps = std::min(steps, static_cast<int>(std::clamp(group_steps, 1.0, 1e9)));
    }
    steps = std::max(1, steps);
    const Tile tile = tile_of(work / (double(steps) * per_sample), width, height);
    return {steps, tile.width, tile.height};
}

base::Result<int> RaycastPass::run(RaycastVariant variant, int width, int height,
                                   const MarchBudget& budget, FrameTarget& target,
                                   gpu::GpuTimer& timer, WorkChunks& chunks) {
    const bool compute = variant.stage == scene::RaycastStage::compute;
    const long long cap = usable_loop_cap(budget);
    const long long needed =
            static_cast<long long>(budget.max_samples_per_ray) * budget.iterations_per_sample;
    if (!compute && cap > 0 && needed > cap) {
        return base::make_error("unsupported_settings",
                                "this GL implementation stops a fragment shader after " +
                                        std::to_string(budget.loop_cap) +
                                        " loop iterations, fewer than these rays need; use "
                                        "the compute stage, which marches them in chunks",
                                "stage");
    }
    const MarchChunks layout =
            plan_march_chunks(budget, width, height, chunks.work_per_chunk(), compute);
    const bool whole_frame = layout.steps >= budget.max_samples_per_ray &&
                             layout.tile_width >= width && layout.tile_height >= height;
    target.ensure(width, height);
    const int before = chunks.count();
    if (!whole_frame) {
        variant.chunked = compute;
        timer.begin();
        const base::Status status =
                compute ? run_compute_chunks(variant, width, height, budget, layout, target, chunks)
                        : run_fragment_tiles(variant, width, height, layout, target, chunks);
        timer.end();
        if (!status) {
            return status.error();
        }
        return chunks.count() - before;
    }
    auto program = program_for(variant);
    if (!program) {
        return program.error();
    }
    glUseProgram((*program)->name());
    timer.begin();
    if (compute) {
        glBindImageTexture(0, target.texture(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                           FrameTarget::image_format);
        glDispatchCompute(static_cast<GLuint>(layout.tile_width / group_side),
                          static_cast<GLuint>(layout.tile_height / group_side), 1);
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
    if (!chunks.continue_after_chunk()) {
        return cancelled_error();
    }
    return 1;
}

// Every tile marches samples [first, first + steps) of its rays before any ray goes further, so
// that a cancelled frame stops after one tile's worth of work. The running sums stay in float in
// `accumulation_`, exactly as they would in the shader's registers, and resolve.comp composites
// them over the background.
base::Status RaycastPass::run_compute_chunks(const RaycastVariant& variant, int width, int height,
                                             const MarchBudget& budget, const MarchChunks& layout,
                                             FrameTarget& target, WorkChunks& chunks) {
    auto program = program_for(variant);
    auto resolve = programs_.compute("resolve.comp");
    if (!program || !resolve) {
        return !program ? program.error() : resolve.error();
    }
    if (!accumulation_ || accumulation_width_ != width || accumulation_height_ != height) {
        accumulation_ = gpu::create_texture(GL_TEXTURE_2D);
        glTextureStorage2D(accumulation_.name(), 1, GL_RGBA32F, width, height);
        accumulation_width_ = width;
        accumulation_height_ = height;
    }
    glUseProgram((*program)->name());
    glBindImageTexture(1, accumulation_.name(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glUniform1i(1, layout.steps);
    const auto groups_x = static_cast<GLuint>(layout.tile_width / group_side);
    const auto groups_y = static_cast<GLuint>(layout.tile_height / group_side);
    for (int first = 0; first < budget.max_samples_per_ray; first += layout.steps) {
        glUniform1i(0, first);
        for (int y = 0; y < height; y += layout.tile_height) {
            for (int x = 0; x < width; x += layout.tile_width) {
                glUniform2i(2, x, y);
                glDispatchCompute(groups_x, groups_y, 1);
                glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
                if (!chunks.continue_after_chunk()) {
                    return cancelled_error();
                }
            }
        }
    }
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    glUseProgram((*resolve)->name());
    glBindTextureUnit(0, accumulation_.name());
    glBindImageTexture(0, target.texture(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                       FrameTarget::image_format);
    glDispatchCompute(static_cast<GLuint>(round_up_to_groups(width) / group_side),
                      static_cast<GLuint>(round_up_to_groups(height) / group_side), 1);
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    return base::Ok{};
}

// The fragment stage cannot resume a ray, so it is cut into tiles of whole rays only.
base::Status RaycastPass::run_fragment_tiles(const RaycastVariant& variant, int width, int height,
                                             const MarchChunks& layout, FrameTarget& target,
                                             WorkChunks& chunks) {
    auto program = program_for(variant);
    if (!program) {
        return program.error();
    }
    glUseProgram((*program)->name());
    glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer());
    glViewport(0, 0, width, height);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glBindVertexArray(empty_vertex_array_.name());
    glEnable(GL_SCISSOR_TEST);
    base::Status status = base::Ok{};
    for (int y = 0; y < height && status; y += layout.tile_height) {
        for (int x = 0; x < width; x += layout.tile_width) {
            glScissor(x, y, layout.tile_width, layout.tile_height);
            glDrawArrays(GL_TRIANGLES, 0, 3);
            if (!chunks.continue_after_chunk()) {
                status = cancelled_error();
                break;
            }
        }
    }
    glDisable(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return status;
}

}  // namespace penumbra::render
