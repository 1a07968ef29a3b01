#include "kept_stills.hpp"

#include "pass_clock.hpp"
#include "work_chunks.hpp"

#include <penumbra/base/assert.hpp>
#include <penumbra/gpu/commands.hpp>

#include <string>

namespace penumbra::render {

KeptStills::KeptStills(std::size_t memory_budget, bool timer_queries)
    : means_(memory_budget)
    , timer_queries_(timer_queries) {}

KeptStills::Key KeptStills::key_of(const scene::FrameRequest& request,
                                   std::uint64_t volume_generation,
                                   std::uint64_t labels_generation) {
    Key key{volume_generation, request.labels.shown() ? labels_generation : 0, request};
    key.request.refinement = {};
    return key;
}

base::Status KeptStills::check_step(const scene::FrameRequest& request,
                                    std::uint64_t volume_generation,
                                    std::uint64_t labels_generation) const {
    const int step = request.refinement.step;
    if (step == 0) {
        return base::Ok{};
    }
    const Mean* mean = means_.peek(key_of(request, volume_generation, labels_generation));
    if (mean != nullptr && mean->frames == step) {
        return base::Ok{};
    }
    return base::make_error(base::ErrorCode::refinement_lost,
                            "refinement step " + std::to_string(step) +
                                    " continues a still frame that is no longer held "
                                    "(evicted, or never kept)",
                            "refinement.step");
}

base::Status KeptStills::accumulate(ProgramCache& programs, const scene::FrameRequest& request,
                                    std::uint64_t volume_generation,
                                    std::uint64_t labels_generation, const FrameTarget& target,
                                    FrameReport& report) {
    const auto start = Clock::now();
    auto program = programs.compute("accumulate.comp");
    if (!program) {
        return program.error();
    }
    const scene::RenderSettings& s = request.settings;
    Key key = key_of(request, volume_generation, labels_generation);
    Mean* mean = nullptr;
    if (request.refinement.step == 0) {
        // A new still of the same frame replaces the old one; room is made before the new mean
        // takes its memory.
        means_.remove_if([&](const auto& kept) { return kept.key == key; });
        const std::size_t bytes = std::size_t{16} * s.width * s.height;
        means_.make_room(bytes);
        mean = &means_.insert(std::move(key),
                              {0, gpu::create_texture_2d(GL_RGBA32F, s.width, s.height)}, bytes);
    } else {
        mean = means_.find(key);
        PENUMBRA_ASSERT(mean != nullptr, "a refinement step continues a kept still");
    }
    gpu::bind_image(0, target.texture(), GL_READ_WRITE, FrameTarget::image_format);
    gpu::bind_image(1, mean->texture, GL_READ_WRITE, GL_RGBA32F);
    gpu::set_uniform(**program, 0, mean->frames);
    gpu::dispatch(**program, gpu::groups_covering(group_side, s.width, s.height),
                  GL_TEXTURE_UPDATE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    report.refinement_step = mean->frames;
    ++mean->frames;
    report.passes.push_back({"accumulate", 0.0, pass_ms_since(start, timer_queries_)});
    return base::Ok{};
}

}  // namespace penumbra::render
