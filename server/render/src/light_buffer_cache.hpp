#pragma once

#include "frame_geometry.hpp"
#include "light_buffer.hpp"
#include "program_cache.hpp"
#include "slice_geometry.hpp"
#include "work_chunks.hpp"

#include <penumbra/base/lru_cache.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/gpu/shader_library.hpp>
#include <penumbra/gpu/timer.hpp>
#include <penumbra/render/frame.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>

namespace penumbra::render {

// The light buffers the renderer keeps, by what their content depends on (LightBufferInputs), so
// that sessions with different lights or transfer functions each keep theirs; least recently used
// evicted first, so that together they stay under the budget.
class LightBufferCache {
public:
    // `timer_queries`: whether the device's GPU timers mean anything (RendererInfo).
    LightBufferCache(ProgramCache& programs, std::size_t memory_budget, bool timer_queries);

    // Binds on unit 2 the buffer `inputs` define, building it (in chunks, with `defines`) when
    // none is held; `slices` carries the per-slice builder's polygons. A cancelled build leaves a
    // partial buffer, which is not kept. A build is timed by `timer`, the frame's own, whose
    // result the renderer reads when the frame completes (the pass's gpu_ms is -1 until then).
    base::Status use(LightBufferInputs inputs, const scene::LightBufferSettings& settings,
                     const FrameGeometry& g, const gpu::Defines& defines, SliceMesh& slices,
                     gpu::GpuTimer& timer, WorkChunks& chunks, FrameReport& report);

    // Drops the buffers of a volume the renderer no longer holds: nothing can reuse them.
    void forget_volume(std::uint64_t volume_generation);

    // The buffer the last light-buffer frame used, null when it has been evicted since.
    [[nodiscard]] const LightBuffer* last_used() const;

    [[nodiscard]] std::uint64_t builds() const { return builds_; }

    [[nodiscard]] std::size_t bytes() const { return buffers_.bytes(); }

private:
    LightBufferBuilder builder_;
    bool timer_queries_;
    base::LruCache<LightBufferInputs, LightBuffer> buffers_;
    std::optional<LightBufferInputs> last_used_;
    std::uint64_t builds_ = 0;
};

}  // namespace penumbra::render
