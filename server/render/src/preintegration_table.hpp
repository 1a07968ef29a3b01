#pragma once

#include "program_cache.hpp"

#include <penumbra/base/result.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/optics/preintegration.hpp>

#include <cstdint>
#include <optional>

namespace penumbra::render {

// The pre-integration table (shaders/include/preintegration.glsl) on the GPU: a 2D RGBA32F
// texture over (front, back) normalised value, built by shaders/preintegration_table.comp from
// the TF texture on unit 1. Kept with the TF texture: built again only when that texture's
// version or the compositing changes.
class PreintegrationTable {
public:
    // `timer_queries`: whether the device's GPU timers mean anything (RendererInfo).
    explicit PreintegrationTable(bool timer_queries, int side = optics::preintegration_table_side);

    // Builds the table for the TF texture of `tf_version` bound on unit 1, unless it holds that
    // one already; returns the time taken when it did.
    base::Result<std::optional<double>> update(ProgramCache& programs, std::uint64_t tf_version,
                                               bool extinction);

    [[nodiscard]] const gpu::Texture& texture() const { return texture_; }

    [[nodiscard]] int side() const { return side_; }

private:
    bool timer_queries_;
    int side_;
    gpu::Texture texture_;
    gpu::Buffer cumulative_;
    std::optional<std::uint64_t> built_version_;
    bool built_extinction_ = false;
};

}  // namespace penumbra::render
