#pragma once

// What the one-view benchmarks (`bench refine`, `bench truth`) start from: a volume loaded from a
// file, the frame the command line's frame options ask for on it, and a renderer of their own
// holding the volume.

#include <penumbra/base/result.hpp>
#include <penumbra/cli/frame_options.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/volume/volume.hpp>

#include <memory>
#include <string>
#include <utility>

namespace penumbra::app {

struct FramedVolume {
    std::shared_ptr<const volume::Volume> volume;
    scene::FrameRequest frame;
    std::unique_ptr<render::Renderer> renderer;
};

inline base::Result<FramedVolume> framed_volume(const cli::po::variables_map& a,
                                                const std::string& path) {
    auto loaded = volume::load_volume(path);
    if (!loaded) {
        return loaded.error();
    }
    FramedVolume framed;
    framed.volume = std::make_shared<const volume::Volume>(std::move(loaded.value()));
    auto frame = cli::frame_request_from(a, *framed.volume);
    if (!frame) {
        return frame.error();
    }
    framed.frame = std::move(*frame);
    auto renderer = render::Renderer::create();
    if (!renderer) {
        return renderer.error();
    }
    framed.renderer = std::move(*renderer);
    if (auto status = framed.renderer->set_volume(framed.volume); !status) {
        return status.error();
    }
    return framed;
}

}  // namespace penumbra::app
