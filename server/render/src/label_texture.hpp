#pragma once

#include "empty_space.hpp"

#include <penumbra/base/result.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/optics/labels.hpp>
#include <penumbra/scene/labels.hpp>
#include <penumbra/volume/label_map.hpp>

#include <glm/mat4x4.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace penumbra::render {

// A label map on the GPU (shaders/include/labels.glsl): its indices as unsigned integer texels
// (R8UI or R16UI), fetched and never filtered, on texture unit 7, and the style table of the
// frame's scene::Labels on unit 8, uploaded when it changes.
class LabelTexture {
public:
    // Uploads `labels`; `generation` tells it apart from every other label map the renderer held
    // (keys of light buffers).
    static base::Result<LabelTexture> upload(std::shared_ptr<const volume::LabelMap> labels,
                                             std::uint64_t generation, int max_3d_texture_size);

    [[nodiscard]] const volume::LabelMap& labels() const { return *labels_; }

    [[nodiscard]] std::uint64_t generation() const { return generation_; }

    [[nodiscard]] std::size_t bytes() const {
        return labels_->indices.data.size() +
               sizeof(std::uint32_t) * (bricks_.starts.size() + bricks_.indices.size());
    }

    // World space of `scan` (as the renderer places it) to the map's voxel index space.
    [[nodiscard]] glm::mat4 world_to_index(const volume::Volume& scan) const;

    // Binds the indices and `styles`, uploading the table unless it is the one uploaded last.
    void bind(const optics::LabelStyleTable& styles);

    // Counts the style tables uploaded: a brick classification made under one holds until the next.
    [[nodiscard]] std::uint64_t styles_version() const { return styles_version_; }

    // The labels of the bricks (`grid`) of `scan`, the volume of generation `scan_generation`:
    // computed for the first frame of each scan, kept on the CPU for the work estimate and on
    // storage buffers 1 and 2 for the brick classification, which bind_brick_labels binds.
    const BrickLabels& brick_labels(const volume::Volume& scan, std::uint64_t scan_generation,
                                    glm::ivec3 grid);
    void bind_brick_labels() const;

    // Which of those bricks' label indices `styles` shows (opacity above 0), for occupied_bricks.
    LabelVisibility visibility(const scene::Labels& styles, const volume::Volume& scan,
                               std::uint64_t scan_generation, glm::ivec3 grid);

private:
    LabelTexture(std::shared_ptr<const volume::LabelMap> labels, std::uint64_t generation,
                 gpu::Texture indices);

    std::shared_ptr<const volume::LabelMap> labels_;
    std::uint64_t generation_ = 0;
    gpu::Texture indices_;
    gpu::Texture styles_;
    std::vector<glm::vec4> uploaded_;  // the style table's texels last uploaded
    std::uint64_t styles_version_ = 0;
    std::uint64_t bricks_of_ = 0;  // the scan generation `bricks_` belongs to; 0: none yet
    BrickLabels bricks_;
    gpu::Buffer brick_starts_;
    gpu::Buffer brick_indices_;
};

}  // namespace penumbra::render
