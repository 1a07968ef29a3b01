#pragma once

#include "frame_target.hpp"
#include "program_cache.hpp"
#include "work_chunks.hpp"

#include <penumbra/base/result.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/gpu/shader_library.hpp>
#include <penumbra/gpu/timer.hpp>
#include <penumbra/scene/box.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <string>

namespace penumbra::render {

// The mode table's kinds are the shaders' SHADOWS and SCATTERING defines.
using Shadows = scene::ShadowKind;
using Scattering = scene::ScatteringKind;

// The effects one ray-cast variant compiles in; everything else is compiled out.
struct RaycastVariant {
    Shadows shadows = Shadows::none;
    Scattering scattering = Scattering::none;
    bool phong = false;
    bool extinction = false;
    scene::Reconstruction reconstruction = scene::Reconstruction::trilinear;
    bool point_light = false;
    bool local_light_lookup = false;    // light-buffer shadows only: scene::LightLookup::local
    bool empty_space_skipping = false;  // the brick occupancy is bound on unit 3
    // With phong and trilinear reconstruction (tricubic gradients come from the B-spline's
    // derivative): the gradient texture is bound on unit 5.
    bool gradient_texture = false;
    bool preintegration = false;  // the pre-integration table is bound on unit 6
    bool labels = false;          // a label map and its styles are bound on units 7 and 8
    scene::RaycastStage stage = scene::RaycastStage::compute;

    bool chunked = false;  // compute stage only; set by RaycastPass when a ray needs it

    [[nodiscard]] gpu::Defines defines() const;
    // The defines the light-buffer builders share with it: how they composite, skip and classify.
    [[nodiscard]] gpu::Defines light_buffer_defines() const;
    [[nodiscard]] std::string key() const;  // "SHADOWS=1 SCATTERING=0 PHONG=1 ... compute"
};

// How many loop iterations one ray may need, against the GL implementation's cap.
struct MarchBudget {
    int max_samples_per_ray = 0;    // samples along the longest ray through the box
    int iterations_per_sample = 1;  // 1 + the inner loops' iterations (shadow rays, shells)
    int loop_cap = 0;               // 0: no cap
};

// The budget of rays through `box` under `settings`, with the light's slab samples resolved and
// the device's `loop_cap`.
MarchBudget march_budget(const scene::RenderSettings& settings, const scene::Box& box,
                         int slab_samples, int loop_cap);

// How a frame's rays are cut into chunks: tiles of the image, each marched `steps` samples at a
// time. One tile covering the image and every step at once is the unchunked frame.
struct MarchChunks {
    int steps = 0;
    int tile_width = 0;  // multiples of the 8 x 8 work groups
    int tile_height = 0;
};

// Chunks of about `work_per_chunk` iterations (0: no limit) that stay under the budget's loop cap;
// `split_steps` is false for the fragment stage, which cannot resume a ray.
MarchChunks plan_march_chunks(const MarchBudget& budget, int width, int height,
                              double work_per_chunk, bool split_steps);

// Runs shaders/raycast.{comp,frag} into the frame target. Programs are compiled on first use of
// a variant and kept. Expects the frame's uniform block bound, the volume and TF textures on units
// 0 and 1, for light-buffer shadows the light buffer on unit 2 and, for empty-space skipping, the
// brick occupancy on unit 3.
class RaycastPass {
public:
    explicit RaycastPass(ProgramCache& programs);

    // Returns how many chunks the frame took (1 unless the rays were marched in chunks); fails
    // with cancelled_error() when `chunks` says the frame was cancelled.
    base::Result<int> run(RaycastVariant variant, int width, int height, const MarchBudget& budget,
                          FrameTarget& target, gpu::GpuTimer& timer, WorkChunks& chunks);

private:
    base::Result<const gpu::Program*> program_for(const RaycastVariant& variant);
    base::Status run_compute_chunks(const RaycastVariant& variant, int width, int height,
                                    const MarchBudget& budget, const MarchChunks& layout,
                                    FrameTarget& target, WorkChunks& chunks);
    base::Status run_fragment_tiles(const RaycastVariant& variant, int width, int height,
                                    const MarchChunks& layout, FrameTarget& target,
                                    WorkChunks& chunks);

    ProgramCache& programs_;
    gpu::VertexArray empty_vertex_array_;
    gpu::Texture accumulation_;
    int accumulation_width_ = 0;
    int accumulation_height_ = 0;
};

}  // namespace penumbra::render
