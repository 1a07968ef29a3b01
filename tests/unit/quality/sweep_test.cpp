// The sweep's settings list: what is measured, in which order, and what it costs in frames.

#include <penumbra/quality/sweep.hpp>

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <tuple>
#include <vector>

namespace penumbra::quality {
namespace {

TEST(SweepSettings, ListModesWithoutSlicesFirstThenEachGridPoint) {
    Sweep sweep;
    sweep.modes = {scene::Mode::sbrc, scene::Mode::half_angle, scene::Mode::phong};
    sweep.slices = {32, 64};
    sweep.resolutions = {128};
    sweep.half_angle_slices = {32};
    sweep.distances = {1.0 / 256, 1.0 / 128};
    sweep.repeat = 2;
    std::vector<std::tuple<scene::Mode, int, int>> listed;
    for (const SweepSetting& s : sweep_settings(sweep)) {
        listed.emplace_back(s.mode, s.slices, s.resolution);
    }
    EXPECT_EQ(listed,
              (std::vector<std::tuple<scene::Mode, int, int>>{{scene::Mode::phong, 0, 0},
                                                              {scene::Mode::half_angle, 32, 128},
                                                              {scene::Mode::sbrc, 32, 128},
                                                              {scene::Mode::sbrc, 64, 128}}));
    // (2 references + 4 settings x 2 distances) x 3 frames + 2 builds x 3 frames.
    EXPECT_EQ(frames_per_view(sweep), (2u + 8u) * 3u + 2u * 3u);
}

// Every setting with each skipping and, where the mode casts rays, each jitter; refined images
// add the kept still and the steps per jittered setting and distance.
TEST(SweepSettings, EverySkippingAndJitterOfTheRayCastModes) {
    Sweep sweep;
    sweep.modes = {scene::Mode::sbrc, scene::Mode::half_angle};
    sweep.slices = {32};
    sweep.resolutions = {128};
    sweep.distances = {1.0 / 256};
    sweep.skipping = {true, false};
    sweep.jitter = {false, true};
    sweep.refinement_steps = {2, 8};
    sweep.repeat = 1;
    std::vector<std::tuple<scene::Mode, bool, bool>> listed;
    for (const SweepSetting& s : sweep_settings(sweep)) {
        listed.emplace_back(s.mode, s.skipping, s.jitter);
    }
    EXPECT_EQ(listed, (std::vector<std::tuple<scene::Mode, bool, bool>>{
                              {scene::Mode::half_angle, true, false},
                              {scene::Mode::half_angle, false, false},
                              {scene::Mode::sbrc, true, false},
                              {scene::Mode::sbrc, true, true},
                              {scene::Mode::sbrc, false, false},
                              {scene::Mode::sbrc, false, true}}));
    // 2 references (skipping on, off) + 6 settings, 2 frames each; 2 jittered settings x (the
    // kept still + 8 steps); 2 builds (skipping on, off) x 2 frames.
    EXPECT_EQ(frames_per_view(sweep), (2u + 6u) * 2u + 2u * 9u + 2u * 2u);

    // Jitter alone: a mode that casts no rays is still measured, unjittered.
    sweep.jitter = {true};
    sweep.skipping = {true};
    listed.clear();
    for (const SweepSetting& s : sweep_settings(sweep)) {
        listed.emplace_back(s.mode, s.skipping, s.jitter);
    }
    EXPECT_EQ(listed,
              (std::vector<std::tuple<scene::Mode, bool, bool>>{
                      {scene::Mode::half_angle, true, false}, {scene::Mode::sbrc, true, true}}));
}

TEST(SweepSettings, ApplySetsTheSkippingAndJitter) {
    scene::FrameRequest request;
    const scene::FrameRequest applied =
            SweepSetting{scene::Mode::dvr, 0, 0, false, true}.applied(request);
    EXPECT_FALSE(applied.settings.empty_space_skipping);
    EXPECT_TRUE(applied.settings.jitter);
}

TEST(SweepSettings, ApplySetsTheSlicesOnlyWhereTheSettingHasThem) {
    scene::FrameRequest request;
    request.settings.light_buffer.slices = 99;
    EXPECT_EQ(SweepSetting{scene::Mode::phong}.applied(request).settings.light_buffer.slices, 99);
    const scene::FrameRequest sbrc = SweepSetting{scene::Mode::sbrc, 64, 128}.applied(request);
    EXPECT_EQ(sbrc.settings.mode, scene::Mode::sbrc);
    EXPECT_EQ(sbrc.settings.light_buffer.slices, 64);
    EXPECT_EQ(sbrc.settings.light_buffer.resolution, 128);
}

// Sweep::images keeps every point's image under its own name: each field that tells two points
// apart changes the name, and the volume's file name becomes a safe stem.
TEST(PointImageName, EveryFieldThatTellsPointsApartChangesTheName) {
    Point p;
    p.volume = "ch2.nii.gz";
    p.light = {10.0, 45.0};
    p.mode = scene::Mode::sbrc;
    p.slices = 128;
    p.resolution = 256;
    p.sample_distance = 1.0 / 256.0;
    EXPECT_EQ(point_image_name(p), "ch2_nii_gz-az10-el45-sbrc-n128-r256-d0.00390625-skip-k0.png");
    std::set<std::string> names{point_image_name(p)};
    const auto differs = [&](Point q) { return names.insert(point_image_name(q)).second; };
    Point q = p;
    q.volume = "ch2bet.nii.gz";
    EXPECT_TRUE(differs(q));
    q = p;
    q.light.elevation = 30.0;
    EXPECT_TRUE(differs(q));
    q = p;
    q.mode = scene::Mode::sbrc_cone;
    EXPECT_TRUE(differs(q));
    q = p;
    q.slices = 64;
    EXPECT_TRUE(differs(q));
    q = p;
    q.resolution = 512;
    EXPECT_TRUE(differs(q));
    q = p;
    q.sample_distance = 1.0 / 2048.0;
    EXPECT_TRUE(differs(q));
    q = p;
    q.empty_space_skipping = false;
    EXPECT_TRUE(differs(q));
    q = p;
    q.jitter = true;
    EXPECT_TRUE(differs(q));
    q.refinement_steps = 4;
    EXPECT_TRUE(differs(q));
}

}  // namespace
}  // namespace penumbra::quality
