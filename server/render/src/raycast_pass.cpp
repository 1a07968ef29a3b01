#include "raycast_pass.hpp"

#include <penumbra/gpu/commands.hpp>
#include <penumbra/scene/frame_work.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra::render {

gpu::Defines RaycastVariant::defines() const {
    return {{"SHADOWS", std::to_string(static_cast<int>(shadows))},
            {"SCATTERING", std::to_string(static_cast<int>(scattering))},
            {"PHONG", phong ? "1" : "0"},
            {"EXTINCTION", extinction ? "1" : "0"},
            {"RECONSTRUCTION", std::to_string(static_cast<int>(reconstruction))},
            {"POINT_LIGHT", point_light ? "1" : "0"},
            {"LOCAL_LIGHT_LOOKUP", local_light_lookup ? "1" : "0"},
            {"EMPTY_SPACE_SKIPPING", empty_space_skipping ? "1" : "0"},
            {"GRADIENT_TEXTURE", gradient_texture ? "1" : "0"},
            {"PREINTEGRATION", preintegration ? "1" : "0"},
            {"LABELS", labels ? "1" : "0"},
            {"CHUNKED", chunked ? "1" : "0"}};
}

gpu::Defines RaycastVariant::light_buffer_defines() const {
    return {{"EXTINCTION", extinction ? "1" : "0"},
            {"RECONSTRUCTION", std::to_string(static_cast<int>(reconstruction))},
            {"EMPTY_SPACE_SKIPPING", empty_space_skipping ? "1" : "0"},
            {"PREINTEGRATION", preintegration ? "1" : "0"},
            {"LABELS", labels ? "1" : "0"}};
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

// The cap less a safety margin for the few iterations outside the march loop; 0: no cap.
long long usable_loop_cap(const MarchBudget& budget) {
    return budget.loop_cap > 0 ? budget.loop_cap - 1000 : 0;
}

}  // namespace

MarchBudget march_budget(const scene::RenderSettings& settings, const scene::Box& box,
                         int slab_samples, int loop_cap) {
    MarchBudget budget;
    budget.max_samples_per_ray = scene::samples_per_ray(settings, box);
    budget.iterations_per_sample =
            scene::iterations_per_sample(settings, budget.max_samples_per_ray, slab_samples);
    budget.loop_cap = loop_cap;
    return budget;
}

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
        return base::make_error(base::ErrorCode::unsupported_settings,
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
    timer.begin();
    if (compute) {
        gpu::bind_image(0, target.texture(), GL_WRITE_ONLY, FrameTarget::image_format);
        gpu::dispatch(**program,
                      gpu::groups_covering(group_side, layout.tile_width, layout.tile_height),
                      GL_TEXTURE_UPDATE_BARRIER_BIT);
    } else {
        gpu::draw_into(target.framebuffer(), width, height, gpu::Blend::none);
        gpu::draw_triangles(**program, empty_vertex_array_, 0, 3);
        gpu::end_drawing();
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
        accumulation_ = gpu::create_texture_2d(GL_RGBA32F, width, height);
        accumulation_width_ = width;
        accumulation_height_ = height;
    }
    const gpu::Program& march = **program;
    gpu::bind_image(1, accumulation_, GL_READ_WRITE, GL_RGBA32F);
    gpu::set_uniform(march, 1, layout.steps);
    const gpu::Groups tile =
            gpu::groups_covering(group_side, layout.tile_width, layout.tile_height);
    for (int first = 0; first < budget.max_samples_per_ray; first += layout.steps) {
        gpu::set_uniform(march, 0, first);
        for (int y = 0; y < height; y += layout.tile_height) {
            for (int x = 0; x < width; x += layout.tile_width) {
                gpu::set_uniform(march, 2, x, y);
                gpu::dispatch(march, tile, GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
                if (!chunks.continue_after_chunk()) {
                    return cancelled_error();
                }
            }
        }
    }
    gpu::memory_barrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    gpu::bind_texture(0, accumulation_);
    gpu::bind_image(0, target.texture(), GL_WRITE_ONLY, FrameTarget::image_format);
    gpu::dispatch(**resolve, gpu::groups_covering(group_side, width, height),
                  GL_TEXTURE_UPDATE_BARRIER_BIT);
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
    gpu::draw_into(target.framebuffer(), width, height, gpu::Blend::none);
    base::Status status = base::Ok{};
    for (int y = 0; y < height && status; y += layout.tile_height) {
        for (int x = 0; x < width; x += layout.tile_width) {
            gpu::set_scissor(x, y, layout.tile_width, layout.tile_height);
            gpu::draw_triangles(**program, empty_vertex_array_, 0, 3);
            if (!chunks.continue_after_chunk()) {
                status = cancelled_error();
                break;
            }
        }
    }
    gpu::end_drawing();
    return status;
}

}  // namespace penumbra::render
