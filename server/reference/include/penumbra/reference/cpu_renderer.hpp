#pragma once

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/volume/label_map.hpp>
#include <penumbra/volume/volume.hpp>

namespace penumbra::reference {

// A double-precision CPU renderer of the same integral the GPU ray caster computes: same camera
// rays, sample positions, trilinear sampling, TF table, opacity correction and lighting model
// (server/optics). It is slow and meant for small images in tests and for accuracy measurements.
// Supports the modes dvr, phong and reference (a shadow ray marched to the light per sample);
// the light-buffer and slicing modes are what it measures. A request that styles labels draws
// `labels` inside the volume (optics/labels.hpp), each sample in the label of its nearest voxel.
base::Result<base::ImageRgbaF> render_cpu(const volume::Volume& volume,
                                          const scene::FrameRequest& request,
                                          const volume::LabelMap* labels = nullptr);

}  // namespace penumbra::reference
