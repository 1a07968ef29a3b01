#pragma once

#include "empty_space.hpp"
#include "label_texture.hpp"
#include "program_cache.hpp"
#include "volume_texture.hpp"

#include <penumbra/base/result.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/render/frame.hpp>
#include <penumbra/volume/volume.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace penumbra::render {

// A volume as the renderer keeps it on the GPU, one entry of its volume cache: the texture and the
// bricks' value ranges, uploaded when the volume is set, and what frames build from them when they
// first need it: the bricks' classification under the current transfer function, the gradient
// texture.
class VolumeEntry {
public:
    // Uploads `volume`; `generation` tells it apart from every other volume the renderer held
    // (keys of light buffers and kept stills).
    static base::Result<VolumeEntry> upload(std::shared_ptr<const volume::Volume> volume,
                                            std::uint64_t generation, int max_3d_texture_size,
                                            int brick_voxels);

    [[nodiscard]] const volume::Volume& volume() const { return *volume_; }

    [[nodiscard]] std::uint64_t generation() const { return generation_; }

    [[nodiscard]] const VolumeTexture& texture() const { return texture_; }

    [[nodiscard]] const EmptySpaceMap& empty_space() const { return empty_space_; }

    // The upload's passes (the texture, the brick ranges), for the next frame's report.
    [[nodiscard]] const std::vector<PassTiming>& upload_passes() const { return upload_passes_; }

    // GPU memory held: the volume's texels as loaded, and the gradient texture once built.
    [[nodiscard]] std::size_t bytes() const;

    // Binds the brick occupancy on unit 3, first classifying the bricks against the TF texture on
    // unit 1 (its upload number `tf_version`) and, where the frame draws a label map, `labels`
    // with its style table bound, unless that was classified already. `timer_queries`: whether
    // the device's GPU timers mean anything (RendererInfo).
    base::Status bind_occupancy(ProgramCache& programs, std::uint64_t tf_version,
                                LabelTexture* labels, bool timer_queries, FrameReport& report);

    // Binds the gradient texture on unit 5, building it the first time (bytes() grows then).
    base::Status bind_gradients(ProgramCache& programs, FrameReport& report);

private:
    VolumeEntry(std::shared_ptr<const volume::Volume> volume, std::uint64_t generation,
                VolumeTexture texture, EmptySpaceMap empty_space,
                std::vector<PassTiming> upload_passes);

    std::shared_ptr<const volume::Volume> volume_;
    std::uint64_t generation_ = 0;
    VolumeTexture texture_;
    EmptySpaceMap empty_space_;
    std::vector<PassTiming> upload_passes_;

    // What the bricks were last classified against: the TF's upload number (0: never), the label
    // map's generation and its style table's version (0, 0: no labels).
    struct Classified {
        std::uint64_t tf_version = 0;
        std::uint64_t labels_generation = 0;
        std::uint64_t styles_version = 0;

        bool operator==(const Classified&) const = default;
    };

    Classified classified_;
    gpu::Texture gradients_;
};

}  // namespace penumbra::render
