// The sweep's settings list: what is measured, in which order, and what it costs in frames.

#include <penumbra/quality/sweep.hpp>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace penumbra::quality
