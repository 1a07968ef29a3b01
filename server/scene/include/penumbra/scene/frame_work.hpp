#pragma once

#include <penumbra/scene/box.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>

namespace penumbra::scene {

// Samples the longest ray takes through the box at the settings' sample distance: it crosses the
// box's diagonal. Jitter moves where in its step each sample lies, never how many there are.
[[nodiscard]] int samples_per_ray(const RenderSettings& settings, const Box& box);

// Bricks the longest ray through a grid of `grid` bricks per axis can enter: the grid's diagonal
// in bricks, plus one for a ray that starts inside a brick. 0 for an empty grid.
[[nodiscard]] int bricks_per_ray(glm::ivec3 grid);

// The bricks a transfer function leaves visible: how many, and the smallest block of the grid
// that holds them all (first and last brick per axis, inclusive). No block when none is visible.
struct OccupiedBricks {
    std::int64_t count = 0;
    glm::ivec3 first{0};
    glm::ivec3 last{-1};
};

// What an estimate may know besides the request and the volume's box.
struct WorkContext {
    // Bricks per axis of the volume's brick grid; 0: the volume has none, so nothing is skipped.
    // Brick (i, j, k) covers [i, i + 1) / grid of the box along each axis, as the shaders cut it.
    glm::ivec3 brick_grid{0};
    // The bricks a ray may sample, where known: those the transfer function leaves visible and
    // the cut does not wholly remove (camera rays and shadow rays march only inside the region).
    // Unknown counts every brick as visible, which keeps the estimate an upper bound.
    std::optional<OccupiedBricks> occupied;
    // The bricks the light-buffer builders may sample, where known: those the transfer function
    // leaves visible, cut or not (their slices span the whole box, and a brick's look asks only
    // the transfer function).
    std::optional<OccupiedBricks> occupied_for_light;
};

// Loop iterations one march of at most `samples` samples through `box` costs, at most: every
// sample without skipping. With it, the client picks the camera as well as the TF, so the bound
// holds for the worst ray, not for an average: a ray enters at most bricks_per_ray bricks and
// spends one loop turn leaping each empty one; in the visible ones it takes a sample per step,
// and its steps are never shorter than sample_distance * L / (L + sample_distance) for a ray
// L long inside the box, so the samples there are at most ceil(C / sample_distance) + 1 + B,
// where B bounds the visible bricks one line crosses (their count, and bricks_per_ray of their
// block) and C its length inside them (the smaller of B bricks' diagonals and the block's
// diagonal). Never more than `samples`: each turn advances the march by at least one sample.
[[nodiscard]] double marched_samples(const RenderSettings& settings, int samples, const Box& box,
                                     const WorkContext& context);

// Loop iterations one light-buffer texel's march costs, at most: `slices` x `slab_samples`
// without skipping. With it, a slab whose stretch of the texel's line lies in empty bricks costs
// one look (the per-slice builder looks once per slab, the marching one once per run of empty
// slabs), and only the slabs that reach into visible bricks take their samples. Slabs are at
// least the box's smallest side / slices long along any line, so a line meets at most
// ceil(C / that) + 2 B slabs that reach into visible bricks (C and B as for marched_samples).
[[nodiscard]] double marched_slab_samples(const RenderSettings& settings, int slab_samples,
                                          const Box& box, const WorkContext& context);

// Inner-loop iterations one ray-cast sample costs in the settings' mode: 1 to classify and
// composite it, plus the shadow ray the reference marches toward the light (up to a whole ray),
// plus the lookups of a light-buffer mode (shell rings, cone taps, and the part of a slab the
// local lookup marches). `slab_samples` is the resolved number of points per light slab
// (optics::resolve_slab_samples). Both the frame's work estimate and the ray caster's loop budget
// read it; the loop budget counts every sample (its loop index counts samples, skipped or not).
[[nodiscard]] int iterations_per_sample(const RenderSettings& settings, int samples_per_ray,
                                        int slab_samples);

// The work one frame asks for, in inner-loop iterations of its shaders (each reads the volume at
// least once), counted before anything runs so that a request too large for the server can be
// refused and a long one cut into chunks. Upper bounds for every camera and light the client may
// choose, not averages: early ray termination, empty space the context does not know of, rays
// shorter than the box's diagonal or missing it only make a frame cheaper.
struct FrameWork {
    // pixels x marched_samples x iterations per sample (with the reference's shadow ray at
    // marched_samples too)
    double ray_casting = 0.0;
    double light_buffer = 0.0;  // the light buffer's texels x marched_slab_samples
    double slicing = 0.0;       // half-angle slicing: slices x (pixels + light texels)
    // A refinement step of a progressive still (request.refinement.step > 0): the whole frame,
    // counted here and not in the parts above. Steps run at the lowest priority, only while no
    // other frame waits, so they never take from a viewer's interactive budget.
    double refinement = 0.0;

    // What the frame takes from the interactive budget: everything but refinement.
    [[nodiscard]] double interactive() const { return ray_casting + light_buffer + slicing; }

    // Everything the frame runs, whatever its priority: what a per-frame ceiling bounds.
    [[nodiscard]] double total() const { return interactive() + refinement; }
};

// The work of `request` on a volume in `box`; `slab_samples` as for iterations_per_sample. The
// light buffer counts in full whether or not a cached one would be reused, so that whether a
// request is accepted does not depend on what other sessions rendered before.
[[nodiscard]] FrameWork estimate_work(const FrameRequest& request, const Box& box, int slab_samples,
                                      const WorkContext& context = {});

}  // namespace penumbra::scene
