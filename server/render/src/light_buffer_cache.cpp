#include "light_buffer_cache.hpp"

#include "pass_clock.hpp"

#include <penumbra/gpu/commands.hpp>

#include <string>
#include <utility>

namespace penumbra::render {

LightBufferCache::LightBufferCache(ProgramCache& programs, std::size_t memory_budget,
                                   bool timer_queries)
    : builder_(programs)
    , timer_queries_(timer_queries)
    , buffers_(memory_budget) {}

base::Status LightBufferCache::use(LightBufferInputs inputs,
                                   const scene::LightBufferSettings& settings,
                                   const FrameGeometry& g, const gpu::Defines& defines,
                                   SliceMesh& slices, gpu::GpuTimer& timer, WorkChunks& chunks,
                                   FrameReport& report) {
    const LightBuffer* buffer = buffers_.find(inputs);
    if (buffer != nullptr) {
        report.light_buffer = LightBufferState::reused;
    } else {
        const auto start = Clock::now();
        if (settings.builder == scene::LightBufferBuilder::per_slice) {
            const double reach =
                    g.light_view && g.light_view->perspective
                            ? point_light_reach(g.box, g.light_view->position, g.travel)
                            : 1.0;
            slices.upload(make_slice_geometry(g.region, optics::RegionUser::light, g.travel,
                                              static_cast<float>(g.light_slicing.min),
                                              static_cast<float>(g.light_slicing.max),
                                              settings.slices, reach));
        }
        const std::size_t bytes = LightBuffer::bytes_for(settings.slices, settings.resolution);
        buffers_.make_room(bytes);  // before the new buffer takes its memory
        LightBuffer built(settings.slices, settings.resolution);
        if (gpu::take_error() == GL_OUT_OF_MEMORY) {
            return base::make_error(base::ErrorCode::gpu_out_of_memory,
                                    "not enough GPU memory for a light buffer of " +
                                            std::to_string(settings.slices) + " x " +
                                            std::to_string(settings.resolution) + "^2",
                                    "light_buffer.resolution");
        }
        if (auto status = builder_.build(built, settings.builder, slices, defines, g.slab_samples,
                                         timer, chunks);
            !status) {
            return status;
        }
        report.passes.push_back({std::string("light_buffer_") + scene::to_string(settings.builder),
                                 -1.0, pass_ms_since(start, timer_queries_)});
        buffer = &buffers_.insert(inputs, std::move(built), bytes);
        ++builds_;
        report.light_buffer = LightBufferState::built;
    }
    gpu::bind_texture(2, buffer->texture());
    last_used_ = std::move(inputs);
    return base::Ok{};
}

void LightBufferCache::forget_volume(std::uint64_t volume_generation) {
    buffers_.remove_if(
            [&](const auto& entry) { return entry.key.volume_generation == volume_generation; });
}

const LightBuffer* LightBufferCache::last_used() const {
    return last_used_ ? buffers_.peek(*last_used_) : nullptr;
}

}  // namespace penumbra::render
