// The occupied bricks the work estimate reads (occupied_bricks, on the CPU, before a frame runs)
// are the bricks that shaders/brick_classify.comp marks occupied, exactly, and the block it names
// is the smallest that holds them: on the real ch2 head, with transfer functions from all
// transparent to all visible.

#include "empty_space.hpp"
#include "program_cache.hpp"

#include <penumbra/gpu/context.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/gpu/shader_library.hpp>
#include <penumbra/optics/region.hpp>
#include <penumbra/scene/box.hpp>
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

// The work estimate's bricks for rays under a cut: those wholly beyond the crop's face are empty
// when the cut tissue casts no shadow, and none when it does (shadow rays still march them).
TEST(BrickOccupancy, BricksTheCutRemovesAreEmptyUnlessTheyCastShadows) {
    auto loaded = volume::load_volume("/usr/share/mricron/templates/ch2.nii.gz");
    ASSERT_TRUE(loaded.ok()) << loaded.error().to_string();
    const BrickRanges ranges = compute_brick_ranges(*loaded, default_brick_voxels);
    const std::vector<glm::vec4> table =
            scene::bake(visible_from(0.2), scene::default_table_size,
                        {loaded->range.min, loaded->range.max, loaded->hounsfield});
    const scene::OccupiedBricks whole = occupied_bricks(ranges, table);
    ASSERT_GT(whole.count, 100);

    const scene::Box box =
            scene::box_for_extent(glm::dvec3(loaded->dims) * loaded->spacing, loaded->axes);
    const scene::PatientPlacement placement = scene::patient_placement(
            loaded->origin, loaded->axes, loaded->spacing, glm::dvec3(loaded->dims));
    scene::Cut left_half;  // world x <= 0 kept
    left_half.crop = {true, placement.to_patient(glm::dvec3(-1.0)),
                      placement.to_patient(glm::dvec3(0.0, 1.0, 1.0))};
    const scene::OccupiedBricks cut =
            occupied_bricks(ranges, table, optics::region_of(box, left_half, placement));
    EXPECT_LT(cut.count, whole.count * 6 / 10);
    EXPECT_GT(cut.count, whole.count * 4 / 10);

    left_half.casts_shadows = true;
    const scene::OccupiedBricks context =
            occupied_bricks(ranges, table, optics::region_of(box, left_half, placement));
    EXPECT_EQ(context.count, whole.count);
}

}  // namespace
}  // namespace penumbra::render
