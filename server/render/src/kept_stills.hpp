#pragma once

#include "frame_target.hpp"
#include "program_cache.hpp"

#include <penumbra/base/lru_cache.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/render/frame.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <cstddef>
#include <cstdint>

namespace penumbra::render {

// Progressive stills: the float mean of each kept still frame and the refinement steps averaged
// into it so far, by the volume and the request it renders (its refinement reset), least recently
// used evicted first under a budget (and by the label map drawn inside the volume).
class KeptStills {
public:
    // `timer_queries`: whether the device's GPU timers mean anything (RendererInfo).
    KeptStills(std::size_t memory_budget, bool timer_queries);

    // Fails with `refinement_lost` when refinement step `request.refinement.step` (> 0) has no
    // kept still to continue: one of the same volume and request with exactly the steps before
    // this one averaged in.
    [[nodiscard]] base::Status check_step(const scene::FrameRequest& request,
                                          std::uint64_t volume_generation,
                                          std::uint64_t labels_generation) const;

    // Averages the frame in `target` into its kept still, a new one for a still frame (step 0),
    // and leaves the mean in the target; the report gets the pass and the step.
    base::Status accumulate(ProgramCache& programs, const scene::FrameRequest& request,
                            std::uint64_t volume_generation, std::uint64_t labels_generation,
                            const FrameTarget& target, FrameReport& report);

    [[nodiscard]] std::size_t bytes() const { return means_.bytes(); }

private:
    struct Key {
        std::uint64_t volume_generation = 0;
        std::uint64_t labels_generation = 0;  // the label map drawn (0: none)
        scene::FrameRequest request;          // its refinement reset

        bool operator==(const Key&) const = default;
    };

    struct Mean {
        int frames = 0;  // frames averaged into `texture`: the still and its refinement steps
        gpu::Texture texture;
    };

    static Key key_of(const scene::FrameRequest& request, std::uint64_t volume_generation,
                      std::uint64_t labels_generation);

    base::LruCache<Key, Mean> means_;
    bool timer_queries_;
};

}  // namespace penumbra::render
