#include "volume_entry.hpp"

#include "gradient_texture.hpp"
#include "pass_clock.hpp"

#include <penumbra/gpu/commands.hpp>

namespace penumbra::render {

VolumeEntry::VolumeEntry(std::shared_ptr<const volume::Volume> volume, std::uint64_t generation,
                         VolumeTexture texture, EmptySpaceMap empty_space,
                         std::vector<PassTiming> upload_passes)
    : volume_(std::move(volume))
    , generation_(generation)
    , texture_(std::move(texture))
    , empty_space_(std::move(empty_space))
    , upload_passes_(std::move(upload_passes)) {}

base::Result<VolumeEntry> VolumeEntry::upload(std::shared_ptr<const volume::Volume> volume,
                                              std::uint64_t generation, int max_3d_texture_size,
                                              int brick_voxels) {
    const auto start = Clock::now();
    auto texture = upload_volume(*volume, max_3d_texture_size);
    if (!texture) {
        return texture.error();
    }
    std::vector<PassTiming> passes{{"upload_volume", 0.0, finished_ms_since(start)}};
    const auto bricks_start = Clock::now();
    EmptySpaceMap empty_space(compute_brick_ranges(*volume, brick_voxels));
    passes.push_back({"brick_ranges", 0.0, finished_ms_since(bricks_start)});
    return VolumeEntry(std::move(volume), generation, std::move(texture.value()),
                       std::move(empty_space), std::move(passes));
}

std::size_t VolumeEntry::bytes() const {
    return volume_->data.size() + (gradients_ ? gradient_texture_bytes(volume_->dims) : 0);
}

base::Status VolumeEntry::bind_occupancy(ProgramCache& programs, std::uint64_t tf_version,
                                         LabelTexture* labels, bool timer_queries,
                                         FrameReport& report) {
    const Classified wanted{tf_version, labels != nullptr ? labels->generation() : 0,
                            labels != nullptr ? labels->styles_version() : 0};
    if (classified_ != wanted) {
        const auto start = Clock::now();
        if (labels != nullptr) {
            labels->brick_labels(*volume_, generation_, empty_space_.grid());
            labels->bind_brick_labels();
        }
        if (auto status = empty_space_.classify(programs, labels != nullptr); !status) {
            return status;
        }
        classified_ = wanted;
        report.passes.push_back({"classify_bricks", 0.0, pass_ms_since(start, timer_queries)});
    }
    gpu::bind_texture(3, empty_space_.occupancy());
    return base::Ok{};
}

base::Status VolumeEntry::bind_gradients(ProgramCache& programs, FrameReport& report) {
    if (!gradients_) {
        const auto start = Clock::now();
        auto gradients = build_gradient_texture(programs, texture_, volume_->dims);
        if (!gradients) {
            return gradients.error();
        }
        gradients_ = std::move(gradients.value());
        report.passes.push_back({"build_gradients", 0.0, finished_ms_since(start)});
    }
    gpu::bind_texture(5, gradients_);
    return base::Ok{};
}

}  // namespace penumbra::render
