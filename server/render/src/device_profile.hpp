#pragma once

#include <penumbra/gpu/context.hpp>
#include <penumbra/render/renderer.hpp>

namespace penumbra::render {

// What the renderer makes of the device its context runs on: the limits it reports, and whether it
// is one of Mesa's software rasterisers (no GPU found), whose timer queries and loop limits the
// passes must work around.
[[nodiscard]] RendererInfo describe_device(const gpu::ContextInfo& context);

// The work per chunk of a frame when RendererOptions leaves it to the device: a software
// rasteriser runs 4e6 in a few tens of milliseconds at its slowest (light-buffer builds), a GPU
// runs a thousand times more in a few milliseconds and would idle on smaller dispatches.
[[nodiscard]] double default_chunk_work(const RendererInfo& info);

}  // namespace penumbra::render
