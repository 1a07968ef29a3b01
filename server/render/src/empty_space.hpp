#pragma once

#include "program_cache.hpp"

#include <penumbra/base/result.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/optics/region.hpp>
#include <penumbra/scene/frame_work.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <array>
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

// The bricks that a TF table leaves visible, by shaders/brick_classify.comp's rule, on the CPU:
// the frame's work estimate needs them before anything is uploaded, so that a request on a mostly
// transparent volume is not refused for samples its rays leap. An empty table (nothing known)
// leaves every brick visible.
// With `region`, a brick that lies wholly outside the region as the light sees it (what neither
// camera rays nor, unless the cut casts shadows, the light ever march through) is empty too.
[[nodiscard]] scene::OccupiedBricks occupied_bricks(const BrickRanges& ranges,
                                                    const std::vector<glm::vec4>& table,
                                                    const optics::Region& region = {});

// A volume's bricks on the GPU: the ranges, uploaded once, and the occupancy that
// shaders/brick_classify.comp derives from them and the current TF table (bound on unit 1).
class EmptySpaceMap {
public:
    EmptySpaceMap() = default;
    explicit EmptySpaceMap(const BrickRanges& ranges);

    // Marks each brick occupied or empty against the TF texture bound on unit 1.
    base::Status classify(ProgramCache& programs) const;

    // The R8UI occupancy grid that shaders/include/empty_space.glsl reads.
    [[nodiscard]] const gpu::Texture& occupancy() const { return occupancy_; }

    [[nodiscard]] glm::ivec3 grid() const { return ranges_on_cpu_.grid; }

    // occupied_bricks of this volume's bricks under `table`.
    // The last few answers are kept: the frames of an unchanged TF and cut (a camera drag) ask
    // again, a frame with a cut the light meets asks twice (with its region and without), and the
    // walk over every brick is a frame's largest CPU cost in a sanitizer's build. The region's box
    // is this volume's, so its half-spaces and counts say which region it is.
    [[nodiscard]] scene::OccupiedBricks occupied_bricks(const std::vector<glm::vec4>& table,
                                                        const optics::Region& region = {}) const {
        const glm::ivec2 counts(region.count, region.light_count);
        const auto kept = std::find_if(answers_.begin(), answers_.end(), [&](const Answer& a) {
            return a.counts == counts && a.half_spaces == region.half_spaces && a.table == table;
        });
        if (kept != answers_.end()) {
            std::rotate(answers_.begin(), kept, kept + 1);  // most recent first
        } else {
            if (answers_.size() == kept_answers) {
                answers_.pop_back();
            }
            answers_.insert(answers_.begin(),
                            Answer{table, region.half_spaces, counts,
                                   render::occupied_bricks(ranges_on_cpu_, table, region)});
        }
        return answers_.front().occupied;
    }

private:
    struct Answer {
        std::vector<glm::vec4> table;
        std::array<optics::HalfSpace, optics::kMaxHalfSpaces> half_spaces;
        glm::ivec2 counts;
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
