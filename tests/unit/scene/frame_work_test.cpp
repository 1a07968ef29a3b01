#include <penumbra/scene/frame_work.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace penumbra::scene {
namespace {

const std::vector<Mode> all_modes = [] {
    std::vector<Mode> all;
    for (const ModeInfo& row : modes()) {
        all.push_back(row.mode);
    }
    return all;
}();

FrameRequest request_in(Mode mode) {
    FrameRequest request;
    request.settings.mode = mode;
    request.settings.width = 64;
    request.settings.height = 48;
    request.settings.light_buffer.slices = 32;
    request.settings.light_buffer.resolution = 64;
    return request;
}

constexpr int slab_samples = 4;

double work_of(const FrameRequest& request, const Box& box = {}) {
    return estimate_work(request, box, slab_samples).total();
}

// Each step makes the frame ask for more of something; the estimate must never fall, and must
// rise wherever the mode does that work at all.
TEST(FrameWork, GrowsWithEverySizeAndStepCount) {
    struct Growth {
        std::string what;
        std::function<void(FrameRequest&)> grow;
        std::function<bool(Mode)> matters;
    };

    const auto always = [](Mode) { return true; };
    const auto ray_cast = [](Mode m) { return m != Mode::half_angle; };
    const auto light = [](Mode m) { return m == Mode::half_angle || uses_light_buffer(m); };
    const std::vector<Growth> growths = {
            {"width", [](FrameRequest& r) { r.settings.width *= 2; }, always},
            {"height", [](FrameRequest& r) { r.settings.height += 7; }, always},
            {"finer sample distance", [](FrameRequest& r) { r.settings.sample_distance /= 3.0; },
             ray_cast},
            {"slices", [](FrameRequest& r) { r.settings.light_buffer.slices *= 2; }, light},
            {"light resolution", [](FrameRequest& r) { r.settings.light_buffer.resolution += 16; },
             light},
            {"shell rings", [](FrameRequest& r) { r.settings.scattering.shell_rings += 1; },
             [](Mode m) { return m == Mode::sbrc_shell; }},
    };
    for (const Mode mode : all_modes) {
        for (const auto& growth : growths) {
            FrameRequest request = request_in(mode);
            double previous = work_of(request);
            ASSERT_GT(previous, 0.0) << to_string(mode);
            for (int step = 0; step < 3; ++step) {
                growth.grow(request);
                const double work = work_of(request);
                if (growth.matters(mode)) {
                    EXPECT_GT(work, previous) << to_string(mode) << ": more " << growth.what;
                } else {
                    EXPECT_EQ(work, previous) << to_string(mode) << ": more " << growth.what;
                }
                previous = work;
            }
        }
    }
}

TEST(FrameWork, MoreSlabSamplesNeverCostLess) {
    for (const Mode mode : all_modes) {
        const FrameRequest request = request_in(mode);
        double previous = 0.0;
        for (int samples = 1; samples <= kMaxSlabSamples; ++samples) {
            const double work = estimate_work(request, {}, samples).total();
            EXPECT_GE(work, previous) << to_string(mode) << " at " << samples << " slab samples";
            previous = work;
        }
    }
}

// A flat box has a shorter diagonal, so shorter rays.
TEST(FrameWork, ShorterRaysCostLess) {
    const Box flat = box_for_extent({1.0, 1.0, 0.1});
    for (const Mode mode : all_modes) {
        if (mode == Mode::half_angle) {
            continue;
        }
        EXPECT_LT(work_of(request_in(mode), flat), work_of(request_in(mode))) << to_string(mode);
    }
}

// The work depends on the box's shape, not on how it is turned: a turned or mirrored volume
// costs what the same volume stored RAS does.
TEST(FrameWork, DoesNotDependOnTheVolumeOrientation) {
    const glm::dvec3 extent{0.8, 1.0, 0.6};
    const glm::dmat3 asr({0, 1, 0}, {0, 0, 1}, {1, 0, 0});
    const glm::dmat3 las({-1, 0, 0}, {0, 1, 0}, {0, 0, 1});
    for (const Mode mode : all_modes) {
        const double ras = work_of(request_in(mode), box_for_extent(extent));
        EXPECT_EQ(work_of(request_in(mode), box_for_extent(extent, las)), ras) << to_string(mode);
        EXPECT_EQ(work_of(request_in(mode), box_for_extent({1.0, 0.6, 0.8}, asr)), ras)
                << to_string(mode);
    }
}

// Counted from the definition: pixels x samples per ray x iterations per sample, plus the light
// buffer's texels x slices x slab samples.
TEST(FrameWork, CountsEachPartOfTheFrame) {
    FrameRequest request = request_in(Mode::sbrc);
    request.settings.sample_distance = 1.0 / 128.0;
    request.settings.light_buffer.lookup = LightLookup::interpolate;
    const Box box;  // the unit cube: a diagonal of sqrt(3)
    const int samples = samples_per_ray(request.settings, box);
    EXPECT_EQ(samples, 223);  // ceil(sqrt(3) * 128) + 1
    const FrameWork work = estimate_work(request, box, slab_samples);
    EXPECT_DOUBLE_EQ(work.ray_casting, 64.0 * 48.0 * 223.0);
    EXPECT_DOUBLE_EQ(work.light_buffer, 64.0 * 64.0 * 32.0 * slab_samples);
    EXPECT_DOUBLE_EQ(work.slicing, 0.0);

    request.settings.light_buffer.lookup = LightLookup::local;
    EXPECT_EQ(iterations_per_sample(request.settings, samples, slab_samples), 2 + slab_samples);
    request.settings.mode = Mode::reference;
    EXPECT_EQ(iterations_per_sample(request.settings, samples, slab_samples), 2 + samples);
    EXPECT_DOUBLE_EQ(estimate_work(request, box, slab_samples).light_buffer, 0.0);

    request.settings.mode = Mode::half_angle;
    const FrameWork slicing = estimate_work(request, box, slab_samples);
    EXPECT_DOUBLE_EQ(slicing.slicing, 32.0 * (64.0 * 48.0 + 64.0 * 64.0));
    EXPECT_DOUBLE_EQ(slicing.ray_casting + slicing.light_buffer, 0.0);
}

// The cost per sample the mode table gives each mode: the shader loops' iterations.
TEST(FrameWork, IterationsPerSampleFollowTheModesLoops) {
    FrameRequest request = request_in(Mode::dvr);
    request.settings.scattering.shell_rings = 3;
    request.settings.light_buffer.lookup = LightLookup::local;
    const int local = 1 + slab_samples;
    const int samples = 100;
    const auto iterations = [&](Mode mode) {
        request.settings.mode = mode;
        return iterations_per_sample(request.settings, samples, slab_samples);
    };
    EXPECT_EQ(iterations(Mode::dvr), 1);
    EXPECT_EQ(iterations(Mode::phong), 1);
    EXPECT_EQ(iterations(Mode::half_angle), 1);
    EXPECT_EQ(iterations(Mode::sbrc), 1 + local);
    EXPECT_EQ(iterations(Mode::sbrc_shell), 4 + 2 * 3 + local);
    EXPECT_EQ(iterations(Mode::sbrc_cone), 10 + local);
    EXPECT_EQ(iterations(Mode::reference), 2 + samples);
    request.settings.light_buffer.lookup = LightLookup::interpolate;
    EXPECT_EQ(iterations(Mode::sbrc_cone), 10);
}

// Jitter moves each sample within its step; the ray takes as many samples either way.
TEST(FrameWork, JitterLeavesTheWorkAsItIs) {
    for (const Mode mode : all_modes) {
        FrameRequest jittered = request_in(mode);
        jittered.settings.jitter = true;
        EXPECT_EQ(work_of(jittered), work_of(request_in(mode))) << to_string(mode);
    }
}

TEST(FrameWork, BricksPerRayCrossTheGridsDiagonal) {
    EXPECT_EQ(bricks_per_ray({0, 0, 0}), 0);
    EXPECT_EQ(bricks_per_ray({1, 1, 1}), 3);      // ceil(sqrt(3)) + 1
    EXPECT_EQ(bricks_per_ray({23, 28, 23}), 44);  // ch2 in 8^3 bricks: ceil(42.9) + 1
}

// Without knowing which bricks are visible, skipping promises nothing: the estimate stays the
// upper bound that decides whether a frame is accepted, with or without skipping.
TEST(FrameWork, SkippingWithNothingKnownKeepsTheUpperBound) {
    const WorkContext unknown{.brick_grid = {23, 28, 23},
                              .occupied = std::nullopt,
                              .occupied_for_light = std::nullopt};
    for (const Mode mode : all_modes) {
        FrameRequest skipping = request_in(mode);
        skipping.settings.empty_space_skipping = true;
        FrameRequest marching = skipping;
        marching.settings.empty_space_skipping = false;
        EXPECT_EQ(estimate_work(skipping, {}, slab_samples, unknown).total(),
                  estimate_work(marching, {}, slab_samples).total())
                << to_string(mode);
    }
}

// A 2 x 2 x 2 block of a 16^3 grid visible: a camera ray, a reference shadow ray and a light
// texel's march take at most the samples that fit along the block's diagonal (the longest line
// through it), a few for the steps and brick faces, and one look per brick the march enters.
TEST(FrameWork, SkippingCountsTheLongestStretchThroughVisibleBricksAndOneLookPerBrick) {
    const OccupiedBricks visible_block{8, glm::ivec3(4), glm::ivec3(5)};
    const WorkContext block{.brick_grid = {16, 16, 16},
                            .occupied = visible_block,
                            .occupied_for_light = visible_block};
    FrameRequest request = request_in(Mode::sbrc);
    request.settings.sample_distance = 1.0 / 128.0;
    request.settings.light_buffer.lookup = LightLookup::interpolate;
    const Box box;
    ASSERT_EQ(samples_per_ray(request.settings, box), 223);
    const double diagonal = std::sqrt(3.0) * 2.0 / 16.0;  // the block's, in the box's units
    const int crossed = bricks_per_ray({2, 2, 2});        // 5 of the 8 at most
    const double marched =
            std::ceil(diagonal * 128.0) + 1.0 + crossed + bricks_per_ray({16, 16, 16});
    EXPECT_DOUBLE_EQ(marched_samples(request.settings, 223, box, block), marched);
    FrameWork work = estimate_work(request, box, slab_samples, block);
    EXPECT_DOUBLE_EQ(work.ray_casting, 64.0 * 48.0 * marched);
    // Slabs are 1/32 of the box long: the ones reaching into the block, each at most 4 samples,
    // and a look at each of the 32 slabs.
    const double sampled_slabs = std::ceil(diagonal * 32.0) + 2.0 * crossed;
    EXPECT_DOUBLE_EQ(work.light_buffer, 64.0 * 64.0 * (sampled_slabs * slab_samples + 32.0));

    request.settings.mode = Mode::reference;
    work = estimate_work(request, box, slab_samples, block);
    EXPECT_DOUBLE_EQ(work.ray_casting, 64.0 * 48.0 * marched * (2.0 + marched));

    // Off, the same context changes nothing; and a ray never costs more than without skipping.
    request.settings.empty_space_skipping = false;
    EXPECT_DOUBLE_EQ(estimate_work(request, box, slab_samples, block).ray_casting,
                     64.0 * 48.0 * 223.0 * (2.0 + 223.0));
    request.settings.empty_space_skipping = true;
    EXPECT_DOUBLE_EQ(marched_samples(request.settings, 10, box, block), 10.0);
    // Nothing visible: one look per brick entered, and per slab.
    const WorkContext nothing{.brick_grid = {16, 16, 16},
                              .occupied = OccupiedBricks{},
                              .occupied_for_light = OccupiedBricks{}};
    EXPECT_DOUBLE_EQ(marched_samples(request.settings, 223, box, nothing),
                     1.0 + bricks_per_ray({16, 16, 16}));
    EXPECT_DOUBLE_EQ(marched_slab_samples(request.settings, slab_samples, box, nothing), 32.0);
}

// A cut that leaves rays nothing visible (every visible brick cut away) makes camera rays cheap,
// but the light-buffer builders still march the visible bricks the cut removed: their slices span
// the whole box and look at the transfer function alone, so the light buffer counts in full.
TEST(FrameWork, BricksACutRemovesAreEmptyForRaysButNotForTheLightBufferBuilders) {
    const OccupiedBricks visible_block{8, glm::ivec3(4), glm::ivec3(5)};
    const WorkContext uncut{.brick_grid = {16, 16, 16},
                            .occupied = visible_block,
                            .occupied_for_light = visible_block};
    const WorkContext cut_away{.brick_grid = {16, 16, 16},
                               .occupied = OccupiedBricks{},
                               .occupied_for_light = visible_block};
    FrameRequest request = request_in(Mode::sbrc);
    request.settings.sample_distance = 1.0 / 128.0;
    const Box box;
    const FrameWork whole = estimate_work(request, box, slab_samples, uncut);
    const FrameWork cut = estimate_work(request, box, slab_samples, cut_away);
    // Rays: one look per brick they enter, no samples.
    EXPECT_DOUBLE_EQ(marched_samples(request.settings, 223, box, cut_away),
                     1.0 + bricks_per_ray({16, 16, 16}));
    EXPECT_LT(cut.ray_casting, whole.ray_casting * 0.6);
    EXPECT_DOUBLE_EQ(cut.light_buffer, whole.light_buffer);
    EXPECT_LT(whole.light_buffer, 64.0 * 64.0 * 32.0 * slab_samples);  // skipping counted
}

// The loop turns of one march with empty-space skipping, as raycast.glsl's classify_sample
// takes them, worked out on the line itself: `count` samples evenly over the line's length
// inside the box, one turn per sample in a visible brick, and one per leap to the first sample
// past the empty brick a sample lies in.
int march_turns(const Box& box, glm::ivec3 grid, const std::function<bool(glm::ivec3)>& visible,
                glm::dvec3 origin, glm::dvec3 direction, double sample_distance) {
    // The line's crossing with the (axis-aligned) box.
    double near = 0.0;
    double far = 1e300;
    for (int axis = 0; axis < 3; ++axis) {
        if (direction[axis] == 0.0) {
            continue;
        }
        const double t0 = (box.min[axis] - origin[axis]) / direction[axis];
        const double t1 = (box.max[axis] - origin[axis]) / direction[axis];
        near = std::max(near, std::min(t0, t1));
        far = std::min(far, std::max(t0, t1));
    }
    const double length = far - near;
    const int count = static_cast<int>(std::max(1.0, std::ceil(length / sample_distance)));
    const double step = length / count;
    const glm::dvec3 brick_size = box.size() / glm::dvec3(grid);
    int turns = 0;
    for (int i = 0; i < count; ++turns) {
        const double t = near + (i + 0.5) * step;
        const glm::dvec3 p = origin + t * direction;
        const glm::ivec3 brick = glm::clamp(glm::ivec3(glm::floor((p - box.min) / brick_size)),
                                            glm::ivec3(0), grid - 1);
        if (visible(brick)) {
            ++i;
            continue;
        }
        double exit = 1e300;
        for (int axis = 0; axis < 3; ++axis) {
            if (direction[axis] == 0.0) {
                continue;
            }
            const double face = box.min[axis] +
                                (brick[axis] + (direction[axis] > 0.0 ? 1 : 0)) * brick_size[axis];
            exit = std::min(exit, (face - p[axis]) / direction[axis]);
        }
        i = std::max(i + 1, i + static_cast<int>(std::ceil(exit / step)));
    }
    return turns;
}

// Found in review: the estimate counted the volume-wide fraction of visible bricks, an average.
// A TF that shows one column of a 32^3 grid (1/1024 of its bricks), seen along the column at a
// fine sample distance, has rays that sample all the way through it: the estimate counted 59
// turns for their 1024, and in the reference mode, whose shadow rays run down the column too,
// about 1/150 of what the frame did.
TEST(FrameWork, AVisibleColumnSeenAlongItIsCountedForEverySampleItsRaysTake) {
    const glm::ivec3 grid{32, 32, 32};
    const glm::ivec3 column{16, 16, 0};
    const OccupiedBricks visible_column{32, column, glm::ivec3(16, 16, 31)};
    const WorkContext context{
            .brick_grid = grid, .occupied = visible_column, .occupied_for_light = visible_column};
    const auto in_column = [&](glm::ivec3 brick) {
        return brick.x == column.x && brick.y == column.y;
    };
    const Box box;
    FrameRequest request = request_in(Mode::dvr);
    request.settings.empty_space_skipping = true;
    request.settings.sample_distance = 1.0 / 1024.0;
    const int samples = samples_per_ray(request.settings, box);
    const double estimate = marched_samples(request.settings, samples, box, context);

    // Down the middle of the column, and at a slant through it from one corner of its end to the
    // opposite corner of the other (the longest line through it).
    const glm::dvec3 brick = box.size() / glm::dvec3(grid);
    const glm::dvec3 column_min = box.min + glm::dvec3(column) * brick;
    const glm::dvec3 column_max = column_min + glm::dvec3(1.0, 1.0, 32.0) * brick;
    const glm::dvec3 middle = 0.5 * (column_min + column_max);
    const int along = march_turns(box, grid, in_column, {middle.x, middle.y, -2.0}, {0, 0, 1},
                                  request.settings.sample_distance);
    EXPECT_EQ(along, 1024);
    const glm::dvec3 slant = glm::normalize(column_max - column_min);
    const glm::dvec3 corner = column_min + 1e-9 * (column_max - column_min);
    const int slanted = march_turns(box, grid, in_column, corner - 2.0 * slant, slant,
                                    request.settings.sample_distance);
    EXPECT_GE(estimate, along);
    EXPECT_GE(estimate, slanted);

    // The reference's shadow rays, with the light behind the camera, run back up the column: the
    // sample k steps in marches k + 1 more. Every pixel may be such a ray.
    request.settings.mode = Mode::reference;
    const double pixels = 64.0 * 48.0;
    double reference_ray = 0.0;
    for (int k = 0; k < along; ++k) {
        reference_ray += 2.0 + (k + 1);
    }
    EXPECT_GE(estimate_work(request, box, slab_samples, context).ray_casting,
              pixels * reference_ray);
}

// Refinement steps of a progressive still are frames of their own at the lowest priority: their
// work is counted apart from the interactive budget, while the still they refine counts in it.
TEST(FrameWork, RefinementStepsDoNotCountAgainstTheInteractiveBudget) {
    for (const Mode mode : all_modes) {
        FrameRequest still = request_in(mode);
        still.settings.jitter = true;
        still.refinement = {true, 0};
        const FrameWork first = estimate_work(still, {}, slab_samples);
        EXPECT_GT(first.interactive(), 0.0) << to_string(mode);
        EXPECT_EQ(first.refinement, 0.0) << to_string(mode);

        FrameRequest step = still;
        step.refinement = {false, 3};
        const FrameWork refining = estimate_work(step, {}, slab_samples);
        EXPECT_EQ(refining.interactive(), 0.0) << to_string(mode);
        EXPECT_EQ(refining.refinement, first.interactive()) << to_string(mode);
        EXPECT_EQ(refining.total(), first.total()) << to_string(mode);
    }
}

// The frame of finding 3 (2048^2 pixels, sample distance 1/4096, the reference's shadow rays)
// asks for about 2e14 iterations, eight orders of magnitude more than a default frame.
TEST(FrameWork, TheHoursLongReferenceFrameIsOrdersOfMagnitudeAboveADefaultOne) {
    FrameRequest huge;
    huge.settings.mode = Mode::reference;
    huge.settings.width = 2048;
    huge.settings.height = 2048;
    huge.settings.sample_distance = 1.0 / 4096.0;
    const double work = work_of(huge);
    EXPECT_GT(work, 1e14);
    EXPECT_GT(work, 1e6 * work_of(FrameRequest{}));
}

}  // namespace
}  // namespace penumbra::scene
