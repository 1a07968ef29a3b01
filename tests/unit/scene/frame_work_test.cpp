#include <penumbra/scene/frame_work.hpp>

#include <gtest/gtest.h>

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
    const WorkContext unknown{.bricks_per_ray = 44};
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

// A quarter of the bricks visible: camera rays, the reference's shadow rays and the light
// buffer's marches take the samples in visible bricks and one grid look per brick they enter.
TEST(FrameWork, SkippingCountsTheVisibleBricksAndOneLookPerBrick) {
    const WorkContext quarter{.bricks_per_ray = 20, .occupied_fraction = 0.25};
    FrameRequest request = request_in(Mode::sbrc);
    request.settings.sample_distance = 1.0 / 128.0;
    request.settings.light_buffer.lookup = LightLookup::interpolate;
    const Box box;
    ASSERT_EQ(samples_per_ray(request.settings, box), 223);
    const double marched = std::ceil(223 * 0.25) + 20;  // 76
    EXPECT_DOUBLE_EQ(marched_samples(request.settings, 223, quarter), marched);
    FrameWork work = estimate_work(request, box, slab_samples, quarter);
    EXPECT_DOUBLE_EQ(work.ray_casting, 64.0 * 48.0 * marched);
    EXPECT_DOUBLE_EQ(work.light_buffer, 64.0 * 64.0 * (std::ceil(32 * slab_samples * 0.25) + 20));

    request.settings.mode = Mode::reference;
    work = estimate_work(request, box, slab_samples, quarter);
    EXPECT_DOUBLE_EQ(work.ray_casting, 64.0 * 48.0 * marched * (2.0 + marched));

    // Off, the same context changes nothing; and a ray never costs more than without skipping.
    request.settings.empty_space_skipping = false;
    EXPECT_DOUBLE_EQ(estimate_work(request, box, slab_samples, quarter).ray_casting,
                     64.0 * 48.0 * 223.0 * (2.0 + 223.0));
    request.settings.empty_space_skipping = true;
    EXPECT_DOUBLE_EQ(marched_samples(request.settings, 10, quarter), 10.0);
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
