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
