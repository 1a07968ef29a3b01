// The occupied bricks the work estimate reads (occupied_bricks, on the CPU, before a frame runs)
// are the bricks that shaders/brick_classify.comp marks occupied, exactly, and the block it names
// is the smallest that holds them: on the real ch2 head, with transfer functions from all
// transparent to all visible.

#include "empty_space.hpp"
#include "label_texture.hpp"
#include "program_cache.hpp"

#include <penumbra/gpu/commands.hpp>
#include <penumbra/gpu/context.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/gpu/shader_library.hpp>
#include <penumbra/optics/region.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/box.hpp>
#include <penumbra/scene/transfer_function.hpp>
#include <penumbra/volume/label_map.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/common.hpp>
#include <glm/matrix.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

namespace penumbra::render {
namespace {

scene::TransferFunction visible_from(double threshold) {
    return {"from " + std::to_string(threshold),
            {{0.0, {1.0, 1.0, 1.0}}},
            {{0.0, 0.0}, {threshold, 0.0}, {std::min(1.0, threshold + 0.01), 0.3}, {1.0, 0.3}}};
}

// The occupancy grid the GPU classified, brick by brick (0 empty, 1 occupied, 2 + i one label).
std::vector<std::uint16_t> read_occupancy(const EmptySpaceMap& map) {
    const glm::ivec3 grid = map.grid();
    // The image stores must land before reading.
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    std::vector<std::uint16_t> occupancy(std::size_t(grid.x) * grid.y * grid.z);
    gpu::read_texture(map.occupancy(), GL_RED_INTEGER, GL_UNSIGNED_SHORT,
                      std::as_writable_bytes(std::span(occupancy)));
    return occupancy;
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
        const std::vector<std::uint16_t> occupancy = read_occupancy(map);
        std::size_t marked = 0;
        glm::ivec3 first = grid;
        glm::ivec3 last(-1);
        for (std::size_t i = 0; i < occupancy.size(); ++i) {
            if (occupancy[i] == 0) {
                continue;
            }
            EXPECT_EQ(occupancy[i], 1) << "no labels, so no brick of one label";
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

// The label index a sample at texture coordinate `t` of `scan` takes: the map's voxel nearest to
// it in the map's own index space (shaders/include/labels.glsl), 0 outside the map.
std::uint32_t label_at(const volume::Volume& scan, const volume::LabelMap& labels, glm::dvec3 t) {
    const volume::Volume& map = labels.indices;
    const glm::dvec3 patient =
            scan.origin + scan.axes * ((t * glm::dvec3(scan.dims) - 0.5) * scan.spacing);
    const glm::dvec3 index = (glm::transpose(map.axes) * (patient - map.origin)) / map.spacing;
    const glm::dvec3 voxel = glm::floor(index + 0.5);
    if (glm::any(glm::lessThan(voxel, glm::dvec3(0.0))) ||
        glm::any(glm::greaterThanEqual(voxel, glm::dvec3(map.dims)))) {
        return 0;
    }
    const std::size_t at = (std::size_t(voxel.z) * map.dims.y + std::size_t(voxel.y)) * map.dims.x +
                           std::size_t(voxel.x);
    return map.type == volume::VoxelType::uint8
                   ? std::to_integer<std::uint32_t>(map.data[at])
                   : reinterpret_cast<const std::uint16_t*>(map.data.data())[at];
}

// A label map drawn inside the scan: each brick lists every label its samples can take (checked
// at random points of every brick, on ch2's own grid and on one 1 mm off and stored left-right
// flipped), the GPU marks empty the bricks whose labels are all hidden and names the label of a
// brick of one, and the CPU's count for the work estimate is the GPU's.
TEST(BrickOccupancy, BricksWhoseLabelsAreAllHiddenAreEmptyAndBricksOfOneLabelSayWhich) {
    auto scan = volume::load_volume("/usr/share/mricron/templates/ch2.nii.gz");
    ASSERT_TRUE(scan.ok()) << scan.error().to_string();
    auto context = gpu::Context::create();
    ASSERT_TRUE(context.ok()) << context.error().to_string();
    const gpu::ShaderLibrary shaders(gpu::default_shader_dir());
    ProgramCache programs(shaders);
    const BrickRanges ranges = compute_brick_ranges(*scan, default_brick_voxels);
    const EmptySpaceMap map(ranges);
    const glm::ivec3 grid = map.grid();
    const std::size_t bricks = std::size_t(grid.x) * grid.y * grid.z;

    gpu::Texture table_texture = gpu::create_texture_1d(GL_RGBA32F, scene::default_table_size);
    const std::vector<glm::vec4> table =
            scene::bake(visible_from(0.05), scene::default_table_size,
                        {scan->range.min, scan->range.max, scan->hounsfield});
    gpu::upload_1d(table_texture, scene::default_table_size, GL_RGBA, GL_FLOAT, table.data());
    gpu::bind_texture(1, table_texture);

    for (const char* file : {"aal.nii.gz", "HarvardOxford-cort-maxprob-thr0-1mm.nii.gz"}) {
        SCOPED_TRACE(file);
        auto loaded = volume::load_label_map(std::string("/usr/share/mricron/templates/") + file);
        ASSERT_TRUE(loaded.ok()) << loaded.error().to_string();
        const auto labels = std::make_shared<const volume::LabelMap>(std::move(loaded.value()));
        auto texture = LabelTexture::upload(labels, 1, 2048);
        ASSERT_TRUE(texture.ok()) << texture.error().to_string();
        const BrickLabels& of_bricks = texture->brick_labels(*scan, 1, grid);
        ASSERT_EQ(of_bricks.starts.size(), bricks + 1);

        std::mt19937 random(7);
        std::uniform_real_distribution<double> within(0.0, 1.0);
        std::size_t one_label = 0;
        std::size_t missing = 0;
        for (std::size_t b = 0; b < bricks; ++b) {
            const glm::dvec3 brick(double(b % grid.x), double(b / grid.x % grid.y),
                                   double(b / grid.x / grid.y));
            const auto first = of_bricks.indices.begin() + of_bricks.starts[b];
            const auto last = of_bricks.indices.begin() + of_bricks.starts[b + 1];
            ASSERT_TRUE(std::is_sorted(first, last));
            one_label += last - first == 1 ? 1 : 0;
            for (int k = 0; k < 24; ++k) {
                const glm::dvec3 t =
                        (brick + glm::dvec3(within(random), within(random), within(random))) /
                        glm::dvec3(grid);
                missing += std::binary_search(first, last, label_at(*scan, *labels, t)) ? 0 : 1;
            }
        }
        EXPECT_EQ(missing, 0u) << "samples whose label their brick does not list";
        EXPECT_GT(one_label, bricks / 2) << "bricks of a single label (most are background)";

        // Every third label hidden, and then every label: GPU and CPU leave out the same bricks.
        scene::Labels styles = render::label_styles(*labels);
        for (const bool all_hidden : {false, true}) {
            for (std::size_t i = 0; i < styles.styles.size(); ++i) {
                styles.styles[i].visible = !all_hidden && i % 3 != 0;
            }
            texture->bind(optics::bake_label_styles(styles));
            texture->bind_brick_labels();
            ASSERT_TRUE(map.classify(programs, true).ok());
            const std::vector<std::uint16_t> occupancy = read_occupancy(map);
            const LabelVisibility shown = texture->visibility(styles, *scan, 1, grid);
            std::int64_t marked = 0;
            std::size_t named = 0;
            for (std::size_t b = 0; b < bricks; ++b) {
                const std::uint32_t count = of_bricks.starts[b + 1] - of_bricks.starts[b];
                const std::uint32_t only = of_bricks.indices[of_bricks.starts[b]];
                marked += occupancy[b] != 0 ? 1 : 0;
                if (occupancy[b] >= 2) {
                    ASSERT_EQ(count, 1u);
                    ASSERT_EQ(occupancy[b] - 2u, only);
                    ASSERT_TRUE(shown.shown[only]);
                    ++named;
                } else if (occupancy[b] == 1) {
                    EXPECT_GT(count, 1u);
                }
            }
            const scene::OccupiedBricks counted = occupied_bricks(ranges, table, {}, shown);
            EXPECT_EQ(counted.count, marked);
            const scene::OccupiedBricks alone = occupied_bricks(ranges, table);
            if (all_hidden) {
                // Only the background is left: the scan's bricks inside the labels go.
                EXPECT_LT(marked, alone.count - 1000);
            } else {
                EXPECT_LT(marked, alone.count);
                EXPECT_GT(named, std::size_t(marked) / 3);
            }
        }
    }
}

}  // namespace
}  // namespace penumbra::render
