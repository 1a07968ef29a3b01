#include "work_chunks.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace penumbra::render {

bool WorkChunks::continue_after_chunk() {
    ++count_;
    if (!cancelled_) {
        return true;
    }
    gpu::Fence this_chunk;
    this_chunk.insert();
    // A fence the GL lost leaves nothing to wait for; a GL error, if any, fails the frame later.
    (void)previous_chunk_.wait();
    previous_chunk_ = std::move(this_chunk);
    return !cancelled_();
}

base::Error cancelled_error() {
    return base::make_error(base::ErrorCode::cancelled,
                            "the frame was cancelled before it was finished", "render");
}

Tile tile_of(double texels, int width, int height) {
    const auto round_up = [](int side) {
        return (side + group_side - 1) / group_side * group_side;
    };
    Tile tile{round_up(width), round_up(height)};
    if (!(texels < double(tile.width) * tile.height)) {
        return tile;
    }
    const double side = std::sqrt(std::max(texels, double(group_side * group_side)));
    tile.width =
            std::clamp(static_cast<int>(side) / group_side * group_side, group_side, tile.width);
    const int rows = static_cast<int>(texels / tile.width) / group_side * group_side;
    tile.height = std::clamp(rows, group_side, tile.height);
    return tile;
}

}  // namespace penumbra::render
