#pragma once

#include "empty_space.hpp"
#include "frame_geometry.hpp"
#include "frame_planner.hpp"

#include <penumbra/base/result.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/scene/frame_work.hpp>

#include <glm/vec4.hpp>

#include <cstddef>
#include <vector>

namespace penumbra::render {

// What a frame may ask for (RendererOptions' max_frame_work and light_buffer_memory_budget).
struct FrameCeilings {
    double max_frame_work = 0.0;
    std::size_t light_buffer_memory_budget = 0;
};

// What the work estimate knows of the volume's empty space under the frame's TF table and cut:
// its rays leap the bricks the table leaves transparent, march none that the region (as the
// light sees it, which holds the camera's) leaves out, and no ray of any camera spends more
// samples in the visible ones than fit along its longest stretch through them. The light-buffer
// builders skip by the table alone. Where a label map is drawn, bricks whose labels `labels`
// hides are left out by both.
[[nodiscard]] scene::WorkContext work_context(const scene::FrameRequest& request,
                                              const EmptySpaceMap& bricks,
                                              const std::vector<glm::vec4>& table,
                                              const optics::Region& region,
                                              const LabelVisibility& labels = {});

// Refuses, before anything runs, a frame over the work ceiling (`too_much_work`) or a light
// buffer that the budget could never hold (`light_buffer_too_large`).
[[nodiscard]] base::Status admit(const scene::FrameRequest& request, const FramePlan& plan,
                                 const FrameGeometry& g, const scene::WorkContext& context,
                                 const FrameCeilings& ceilings);

}  // namespace penumbra::render
