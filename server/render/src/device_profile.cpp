#include "device_profile.hpp"

namespace penumbra::render {

RendererInfo describe_device(const gpu::ContextInfo& context) {
    RendererInfo info{context.platform,
                      context.vendor,
                      context.renderer,
                      context.version,
                      context.max_3d_texture_size,
                      context.max_texture_size,
                      context.max_array_texture_layers};
    info.software = info.renderer.find("llvmpipe") != std::string::npos ||
                    info.renderer.find("softpipe") != std::string::npos;
    info.gpu_timer_queries = !info.software;
    info.max_shader_loop_iterations = info.software ? 65535 : 0;
    info.frames_in_flight = info.software ? 1 : 2;
    return info;
}

double default_chunk_work(const RendererInfo& info) {
    return info.software ? 4e6 : 4e9;
}

}  // namespace penumbra::render
