#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/gpu/fence.hpp>
#include <penumbra/render/renderer.hpp>

#include <limits>

namespace penumbra::render {

// A frame's GPU work issued in chunks of about `work_per_chunk` inner-loop iterations. After
// each chunk the renderer waits for the GPU to finish the chunk before it and asks whether the
// frame is still wanted, so a cancelled frame stops within two chunks instead of holding the
// render thread to its end, while the GPU always has the latest chunk to work on and the frame's
// last chunk is left to run behind the next frame's work (Renderer::submit waits for nothing).
// Without a predicate nobody can cancel the frame: it goes in as few dispatches as the GL allows.
class WorkChunks {
public:
    WorkChunks(double work_per_chunk, const CancelPredicate& cancelled)
        : work_per_chunk_(cancelled ? work_per_chunk : std::numeric_limits<double>::infinity())
        , cancelled_(cancelled) {}

    [[nodiscard]] double work_per_chunk() const { return work_per_chunk_; }

    // Whether the frame was cancelled, without waiting for anything.
    [[nodiscard]] bool cancelled() const { return cancelled_ && cancelled_(); }

    // Called after issuing one chunk: waits until the GPU has finished the chunk before it (only
    // where someone may cancel: otherwise the chunks queue up) and returns false when the frame
    // was cancelled.
    [[nodiscard]] bool continue_after_chunk();

    // Chunks issued so far.
    [[nodiscard]] int count() const { return count_; }

private:
    double work_per_chunk_;
    const CancelPredicate& cancelled_;
    int count_ = 0;
    gpu::Fence previous_chunk_;
};

// The error a cancelled frame fails with.
base::Error cancelled_error();

// Tiles of an image (or of a light-buffer layer) worked on by 8 x 8 work groups.
inline constexpr int group_side = 8;

struct Tile {
    int width = 0;  // multiples of group_side
    int height = 0;
};

// A tile of about `texels` (at least one work group), as square as the image allows; the whole
// image, rounded up to work groups, when `texels` covers it.
[[nodiscard]] Tile tile_of(double texels, int width, int height);

}  // namespace penumbra::render
