#pragma once

#include <penumbra/scene/box.hpp>
#include <penumbra/scene/frame_request.hpp>

namespace penumbra::scene {

// Samples the longest ray takes through the box at the settings' sample distance: it crosses the
// box's diagonal.
[[nodiscard]] int samples_per_ray(const RenderSettings& settings, const Box& box);

// Inner-loop iterations one ray-cast sample costs in the settings' mode: 1 to classify and
// composite it, plus the shadow ray the reference marches toward the light (up to a whole ray),
// plus the lookups of a light-buffer mode (shell rings, cone taps, and the part of a slab the
// local lookup marches). `slab_samples` is the resolved number of points per light slab
// (optics::resolve_slab_samples). Both the frame's work estimate and the ray caster's loop budget
// read it.
[[nodiscard]] int iterations_per_sample(const RenderSettings& settings, int samples_per_ray,
                                        int slab_samples);

// The work one frame asks for, in inner-loop iterations of its shaders (each reads the volume at
// least once), counted before anything runs so that a request too large for the server can be
// refused and a long one cut into chunks. Upper bounds: early ray termination, empty space and
// rays that miss the box only make a frame cheaper.
struct FrameWork {
    double ray_casting = 0.0;   // pixels x samples per ray x iterations per sample
    double light_buffer = 0.0;  // the light buffer's texels x slices x slab samples
    double slicing = 0.0;       // half-angle slicing: slices x (pixels + light texels)

    [[nodiscard]] double total() const { return ray_casting + light_buffer + slicing; }
};

// The work of `request` on a volume in `box`; `slab_samples` as for iterations_per_sample. The
// light buffer counts in full whether or not a cached one would be reused, so that whether a
// request is accepted does not depend on what other sessions rendered before.
[[nodiscard]] FrameWork estimate_work(const FrameRequest& request, const Box& box,
                                      int slab_samples);

}  // namespace penumbra::scene
