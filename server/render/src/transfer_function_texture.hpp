#pragma once

#include <penumbra/gpu/objects.hpp>

#include <glm/vec4.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace penumbra::render {

// The frame's baked TF table on the GPU (a 1D RGBA32F texture of scene::default_table_size
// entries, filtered linearly), uploaded again only when the table changes.
class TransferFunctionTexture {
public:
    // Uploads `table` unless the texture holds it already; returns the time taken when it did.
    std::optional<double> update(const std::vector<glm::vec4>& table);

    [[nodiscard]] const gpu::Texture& texture() const { return texture_; }

    // Counts the uploads, so that what was classified against a table knows when it changed.
    [[nodiscard]] std::uint64_t version() const { return version_; }

private:
    gpu::Texture texture_;
    std::vector<glm::vec4> table_;  // what texture_ holds
    std::uint64_t version_ = 0;
};

}  // namespace penumbra::render
