#pragma once

#include <penumbra/volume/volume.hpp>

namespace penumbra::test {

// Volumes with known answers for tests; never a stand-in for real data in demos or benchmarks.

// A float volume of `n`^3 voxels holding `inside` within a sphere of radius `radius` (fraction of
// the half-extent) around the centre and `outside` elsewhere.
volume::Volume sphere_volume(unsigned n, float radius, float inside = 1.0f, float outside = 0.0f);

// A float volume of `n`^3 voxels falling linearly from 1 at the centre to 0 at distance n/2:
// smooth, so GPU and CPU sample positions that differ by rounding see nearly the same value.
volume::Volume radial_volume(unsigned n);

// A float volume whose value is constant.
volume::Volume constant_volume(glm::uvec3 dims, float value);

// A float volume with value 1 for voxels whose z index lies in [z_begin, z_end) and 0 elsewhere.
volume::Volume slab_volume(glm::uvec3 dims, unsigned z_begin, unsigned z_end);

// A shadow-test scene of n^3 float voxels, lit along -x: a "receiver" column (value 1) for x in
// [n/8, 3n/8), and a "slab" (value 0.5) for x in [3n/4, 7n/8) that covers only y < n/2, so half
// of the receiver lies in the slab's shadow.
volume::Volume shadow_scene(unsigned n);

}  // namespace penumbra::test
