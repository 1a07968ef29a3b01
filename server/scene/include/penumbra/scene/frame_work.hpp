#pragma once

#include <penumbra/scene/box.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <glm/vec3.hpp>

namespace penumbra::scene {

// Samples the longest ray takes through the box at the settings' sample distance: it crosses the
// box's diagonal. Jitter moves where in its step each sample lies, never how many there are.
[[nodiscard]] int samples_per_ray(const RenderSettings& settings, const Box& box);

// Bricks the longest ray through a grid of `grid` bricks per axis can enter: the grid's diagonal
// in bricks, plus one for a ray that starts inside a brick. 0 for an empty grid.
[[nodiscard]] int bricks_per_ray(glm::ivec3 grid);

// What an estimate may know besides the request and the volume's box.
struct WorkContext {
    // Bricks the longest ray can enter (bricks_per_ray of the volume's brick grid); 0: the
    // volume has no brick grid, so nothing is skipped.
    int bricks_per_ray = 0;
    // The fraction of the volume's bricks the transfer function leaves visible, where it is
    // known. With empty-space skipping a ray marches only the samples in visible bricks and
    // leaps each transparent one at the cost of one look at the grid; 1 (nothing known, every
    // brick visible) keeps the estimate an upper bound.
    double occupied_fraction = 1.0;
};

// Loop iterations one march of `samples` samples costs: all of them without skipping; with it,
// the fraction in visible bricks plus one grid look per brick the march enters.
[[nodiscard]] double marched_samples(const RenderSettings& settings, int samples,
                                     const WorkContext& context);

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
// refused and a long one cut into chunks. Upper bounds: early ray termination, empty space the
// context does not know of and rays that miss the box only make a frame cheaper.
struct FrameWork {
    double ray_casting = 0.0;   // pixels x samples per ray x iterations per sample
    double light_buffer = 0.0;  // the light buffer's texels x slices x slab samples
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
