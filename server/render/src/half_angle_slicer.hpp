#pragma once

#include "frame_geometry.hpp"
#include "frame_target.hpp"
#include "program_cache.hpp"
#include "slice_geometry.hpp"
#include "work_chunks.hpp"

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/gpu/shader_library.hpp>
#include <penumbra/gpu/timer.hpp>

#include <string>

namespace penumbra::render {

// Half-angle slicing (Kniss et al. 2002), the baseline the paper beats: slices perpendicular to
// the half vector of view and light, each drawn into the eye buffer lit by the light buffer, then
// into the light buffer. 2n draws per frame. Expects the frame's uniform block bound (with the
// half-angle axis and the camera's view-projection filled in) and the volume and TF textures on
// units 0 and 1.
class HalfAngleSlicer {
public:
    explicit HalfAngleSlicer(ProgramCache& programs);

    // Slices perpendicular to the frame's half-angle axis, each cut to what its region keeps: for
    // the eye pass, which samples the slice plane alone, exactly to what camera rays keep (so no
    // fragment asks the region); for the light pass, whose fragments read a slab along the light's
    // rays, to what the light meets, widened by that slab. With the eye and the light on the same
    // side, composited with "under"; otherwise back to front with "over". Issued in groups of
    // slices; fails with cancelled_error() when `chunks` says the frame was cancelled.
    base::Status run(const FrameGeometry& g, int width, int height, int light_resolution,
                     const gpu::Defines& defines, FrameTarget& target, gpu::GpuTimer& timer,
                     WorkChunks& chunks);

    // The light buffer after the last slice, as a grey image.
    [[nodiscard]] base::ImageRgba8 light_image() const;

private:
    void ensure_buffers(int width, int height, int light_resolution);
    void cut_slices(const FrameGeometry& g);

    ProgramCache& programs_;
    SliceMesh eye_slices_;
    SliceMesh light_slices_;
    gpu::Texture eye_;
    gpu::Framebuffer eye_framebuffer_;
    gpu::Texture light_;
    gpu::Framebuffer light_framebuffer_;
    int width_ = 0;
    int height_ = 0;
    int light_resolution_ = 0;
};

}  // namespace penumbra::render
