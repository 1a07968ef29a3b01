#pragma once

#include "program_cache.hpp"

#include <penumbra/base/result.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/optics/region.hpp>
#include <penumbra/scene/frame_work.hpp>
#include <penumbra/volume/label_map.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

namespace penumbra::render {

// Voxels per brick side when RendererOptions leaves it open. On llvmpipe with ch2 (181 x 217 x
// 181) 8 leaps closer to the skin than 16 and classifies in well under a millisecond either way.
inline constexpr int default_brick_voxels = 8;

// The value range of every brick of a volume, in the normalised values the shaders classify
// ([0, 1] over the volume's range). Brick (i, j, k) of a grid of G bricks per axis covers
// texture coordinates [i, i + 1) / G, ...; its range spans every voxel a trilinear sample there
// can read: the voxels inside and a one-voxel border around them.
struct BrickRanges {
    glm::ivec3 grid{0};              // bricks per axis: ceil(dims / brick_voxels)
    std::vector<glm::vec2> min_max;  // x fastest, then y, then z
};

BrickRanges compute_brick_ranges(const volume::Volume& volume, int brick_voxels);

// The labels each brick's samples can take where a label map is drawn inside the volume: per
// brick the distinct label indices (0: the background, or a point outside the map), ascending, of
// the map's voxels nearest to any point of the brick (shaders/include/labels.glsl's rule, with a
// margin for rounding). A brick whose labels are all hidden is empty; one of a single label lets
// its samples skip the label fetch.
struct BrickLabels {
    glm::ivec3 grid{0};
    std::vector<std::uint32_t> starts;  // brick b's indices are indices[starts[b], starts[b + 1])
    std::vector<std::uint32_t> indices;
};

// `grid` is the brick grid of `scan` (BrickRanges::grid); the two share patient space.
BrickLabels compute_brick_labels(const volume::Volume& scan, glm::ivec3 grid,
                                 const volume::LabelMap& labels);

// Which label indices a frame's styles leave visible (opacity above 0), as brick_classify.comp
// reads them from the style table: what a brick's labels are checked against.
struct LabelVisibility {
    const BrickLabels* bricks = nullptr;  // null: no label map drawn, the labels decide nothing
    std::vector<bool> shown;              // by label index, the background's at 0
    std::uint64_t generation = 0;         // of the label map (render::LabelTexture)

    bool operator==(const LabelVisibility& other) const {
        return (bricks == nullptr) == (other.bricks == nullptr) && shown == other.shown &&
               generation == other.generation;
    }
};

// The bricks that a TF table leaves visible, by shaders/brick_classify.comp's rule, on the CPU:
// the frame's work estimate needs them before anything is uploaded, so that a request on a mostly
// transparent volume is not refused for samples its rays leap. An empty table (nothing known)
// leaves every brick visible.
// With `region`, a brick that lies wholly outside the region as the light sees it (what neither
// camera rays nor, unless the cut casts shadows, the light ever march through) is empty too; with
// `labels`, one whose labels are all hidden.
[[nodiscard]] scene::OccupiedBricks occupied_bricks(const BrickRanges& ranges,
                                                    const std::vector<glm::vec4>& table,
                                                    const optics::Region& region = {},
                                                    const LabelVisibility& labels = {});

// A volume's bricks on the GPU: the ranges, uploaded once, and the occupancy that
// shaders/brick_classify.comp derives from them and the current TF table (bound on unit 1).
class EmptySpaceMap {
public:
    EmptySpaceMap() = default;
    explicit EmptySpaceMap(const BrickRanges& ranges);

    // Marks each brick occupied or empty against the TF texture bound on unit 1 and, where a
    // label map is drawn (`labels`: its bricks' labels on storage buffers 1 and 2), the label
    // style table bound on unit 8.
    base::Status classify(ProgramCache& programs, bool labels = false) const;

    // The R16UI occupancy grid that shaders/include/empty_space.glsl reads: 0 empty, 1 occupied,
    // 2 + i occupied and every sample in label index i.
    [[nodiscard]] const gpu::Texture& occupancy() const { return occupancy_; }

    [[nodiscard]] glm::ivec3 grid() const { return ranges_on_cpu_.grid; }

    // occupied_bricks of this volume's bricks under `table`.
    // The last few answers are kept: the frames of an unchanged TF and cut (a camera drag) ask
    // again, a frame with a cut the light meets asks twice (with its region and without), and the
    // walk over every brick is a frame's largest CPU cost in a sanitizer's build. The region's box
    // is this volume's, so its half-spaces and counts say which region it is.
    [[nodiscard]] scene::OccupiedBricks occupied_bricks(const std::vector<glm::vec4>& table,
                                                        const optics::Region& region = {},
                                                        const LabelVisibility& labels = {}) const {
        const glm::ivec2 counts(region.count, region.light_count);
        const auto kept = std::find_if(answers_.begin(), answers_.end(), [&](const Answer& a) {
            return a.counts == counts && a.half_spaces == region.half_spaces && a.table == table &&
                   a.labels == labels;
        });
        if (kept != answers_.end()) {
            std::rotate(answers_.begin(), kept, kept + 1);  // most recent first
        } else {
            if (answers_.size() == kept_answers) {
                answers_.pop_back();
            }
            answers_.insert(answers_.begin(),
                            Answer{table, region.half_spaces, counts, labels,
                                   render::occupied_bricks(ranges_on_cpu_, table, region, labels)});
        }
        return answers_.front().occupied;
    }

private:
    struct Answer {
        std::vector<glm::vec4> table;
        std::array<optics::HalfSpace, optics::kMaxHalfSpaces> half_spaces;
        glm::ivec2 counts;
        LabelVisibility labels;
        scene::OccupiedBricks occupied;
    };

    static constexpr std::size_t kept_answers = 4;

    BrickRanges ranges_on_cpu_;  // kept for the work estimate, which runs before the GPU does
    // Used by the render thread only, as the map itself is.
    mutable std::vector<Answer> answers_;
    gpu::Texture ranges_;
    gpu::Texture occupancy_;
    gpu::Buffer visible_entries_;
};

}  // namespace penumbra::render
