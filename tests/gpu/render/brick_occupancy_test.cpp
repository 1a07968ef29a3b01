// The occupied bricks the work estimate reads (occupied_bricks, on the CPU, before a frame runs)
// are the bricks that shaders/brick_classify.comp marks occupied, exactly, and the block it names
// is the smallest that holds them: on the real ch2 head, with transfer functions from all
// transparent to all visible.

#include "empty_space.hpp"
#include "program_cache.hpp"

#include <penumbra/gpu/context.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/gpu/shader_library.hpp>
#include <penumbra/scene/transfer_function.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/common.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::render {
namespace {

scene::TransferFunction visible_from(double threshold) {
    return {"from " + std::to_string(threshold),
            {{0.0, {1.0, 1.0, 1.0}}},
            {{0.0, 0.0}, {threshold, 0.0}, {std::min(1.0, threshold + 0.01), 0.3}, {1.0, 0.3}}};
}

TEST(BrickOccupancy, TheCpuCountsTheBricksTheGpuMarksOccupied) {
    auto loaded = volume::load_volume("/usr/share/mricron/templates/ch2.nii.gz");
    ASSERT_TRUE(loaded.ok()) << loaded.error().to_string()
                             << " (the install step gets it from Debian's mricron-data)";
    auto context = gpu::Context::create();
    ASSERT_TRUE(context.ok()) << context.error().to_string();
    const gpu::ShaderLibrary shaders(gpu::default_shader_dir());
    ProgramCache programs(shaders);
    const BrickRanges ranges = compute_brick_ranges(*loaded, default_brick_voxels);
    const EmptySpaceMap map(ranges);
    const glm::ivec3 grid = map.grid();
    const std::size_t bricks = std::size_t(grid.x) * grid.y * grid.z;

    gpu::Texture table_texture = gpu::create_texture(GL_TEXTURE_1D);
    glTextureStorage1D(table_texture.name(), 1, GL_RGBA32F, scene::default_table_size);
    glBindTextureUnit(1, table_texture.name());

    std::vector<scene::TransferFunction> functions = {
            {"transparent", {}, {}}, {"visible", {{0.0, {1.0, 1.0, 1.0}}}, {{0.0, 0.2}}}};
    for (const double threshold : {0.05, 0.2, 0.45, 0.7, 0.95}) {
        functions.push_back(visible_from(threshold));
    }
    functions.push_back(scene::preset("mri_skin").value());
    std::size_t partly = 0;
    for (const scene::TransferFunction& tf : functions) {
        SCOPED_TRACE(tf.name);
        const std::vector<glm::vec4> table =
                scene::bake(tf, scene::default_table_size,
                            {loaded->range.min, loaded->range.max, loaded->hounsfield});
        glTextureSubImage1D(table_texture.name(), 0, 0, scene::default_table_size, GL_RGBA,
                            GL_FLOAT, table.data());
        ASSERT_TRUE(map.classify(programs).ok());
        // The grid's rows are not 4-byte multiples; the image stores must land before reading.
        glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        std::vector<std::uint8_t> occupancy(bricks);
        glGetTextureImage(map.occupancy().name(), 0, GL_RED_INTEGER, GL_UNSIGNED_BYTE,
                          static_cast<GLsizei>(occupancy.size()), occupancy.data());
        std::size_t marked = 0;
        glm::ivec3 first = grid;
        glm::ivec3 last(-1);
        for (std::size_t i = 0; i < occupancy.size(); ++i) {
            if (occupancy[i] == 0) {
                continue;
            }
            const glm::ivec3 brick(static_cast<int>(i % std::size_t(grid.x)),
                                   static_cast<int>(i / std::size_t(grid.x) % std::size_t(grid.y)),
                                   static_cast<int>(i / std::size_t(grid.x) / std::size_t(grid.y)));
            ++marked;
            first = glm::min(first, brick);
            last = glm::max(last, brick);
        }
        const scene::OccupiedBricks occupied = occupied_bricks(ranges, table);
        EXPECT_EQ(occupied.count, static_cast<std::int64_t>(marked))
                << marked << " of " << bricks << " bricks marked on the GPU";
        if (marked > 0) {
            EXPECT_EQ(occupied.first, first);
            EXPECT_EQ(occupied.last, last);
        }
        const scene::OccupiedBricks held = map.occupied_bricks(table);
        EXPECT_EQ(held.count, occupied.count);
        EXPECT_EQ(held.first, occupied.first);
        EXPECT_EQ(held.last, occupied.last);
        partly += marked > 0 && marked < bricks ? 1 : 0;
    }
    EXPECT_GE(partly, 4u);  // the thresholds cut through the head's values
}

}  // namespace
}  // namespace penumbra::render
