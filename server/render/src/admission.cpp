#include "admission.hpp"

#include "light_buffer.hpp"

#include <cstdio>
#include <string>

namespace penumbra::render {
namespace {

std::string mebibytes(std::size_t bytes) {
    return std::to_string(bytes >> 20) + " MiB";
}

std::string scientific(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2g", value);
    return text;
}

}  // namespace

scene::WorkContext work_context(const scene::FrameRequest& request, const EmptySpaceMap& bricks,
                                const std::vector<glm::vec4>& table, const optics::Region& region,
                                const LabelVisibility& labels) {
    if (!request.settings.empty_space_skipping) {
        return {};
    }
    // Each frame walks the bricks here: once when nothing is cut away for the light.
    const scene::OccupiedBricks visible = bricks.occupied_bricks(table, {}, labels);
    if (region.count_for(optics::RegionUser::light) == 0) {
        return {bricks.grid(), visible, visible};
    }
    return {bricks.grid(), bricks.occupied_bricks(table, region, labels), visible};
}

base::Status admit(const scene::FrameRequest& request, const FramePlan& plan,
                   const FrameGeometry& g, const scene::WorkContext& context,
                   const FrameCeilings& ceilings) {
    const scene::FrameWork work = scene::estimate_work(request, g.box, g.slab_samples, context);
    if (work.total() > ceilings.max_frame_work) {
        return base::make_error(
                base::ErrorCode::too_much_work,
                "this frame asks for about " + scientific(work.total()) +
                        " shader iterations (image pixels x the samples the longest ray can "
                        "take, where empty space is skipped those that fit in the bricks the "
                        "transfer function leaves visible plus one per brick leapt, x the mode's "
                        "cost per sample, plus light-buffer texels x the slab samples one can "
                        "take), more than this server's ceiling of " +
                        scientific(ceilings.max_frame_work) +
                        " per frame; use a smaller image, a larger sample distance or fewer "
                        "slices",
                "settings");
    }
    if (plan.needs_light_buffer) {
        const scene::LightBufferSettings& lb = request.settings.light_buffer;
        const std::size_t bytes = LightBuffer::bytes_for(lb.slices, lb.resolution);
        if (bytes > ceilings.light_buffer_memory_budget) {
            return base::make_error(
                    base::ErrorCode::light_buffer_too_large,
                    "a light buffer of " + std::to_string(lb.slices) + " slices of " +
                            std::to_string(lb.resolution) + "^2 texels needs " + mebibytes(bytes) +
                            ", more than the " + mebibytes(ceilings.light_buffer_memory_budget) +
                            " this server keeps for light buffers; use fewer slices or a lower "
                            "resolution",
                    "light_buffer");
        }
    }
    return base::Ok{};
}

}  // namespace penumbra::render
