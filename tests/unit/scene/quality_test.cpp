#include <penumbra/scene/quality.hpp>

#include <gtest/gtest.h>

#include <limits>

namespace penumbra::scene {
namespace {

std::vector<QualitySample> table() {
    // Two volumes measured at 256x256; the slowest frame of a setting decides whether it fits.
    return {
            {Mode::phong, 0, 0, 1.0 / 256, 40.0, 18.0, 256, 256},
            {Mode::phong, 0, 0, 1.0 / 256, 50.0, 18.4, 256, 256},
            {Mode::sbrc, 64, 128, 1.0 / 256, 60.0, 22.0, 256, 256},
            {Mode::sbrc, 64, 128, 1.0 / 256, 90.0, 24.0, 256, 256},
            {Mode::sbrc, 256, 256, 1.0 / 256, 150.0, 28.0, 256, 256},
            {Mode::reference, 0, 0, 1.0 / 256, 400.0, std::numeric_limits<double>::infinity(), 256,
             256},
    };
}

TEST(ChooseQuality, PicksTheMostAccurateSettingWhoseSlowestFrameFits) {
    auto choice = choose_quality(table(), 100.0, 256, 256);
    ASSERT_TRUE(choice.has_value());
    EXPECT_EQ(choice->mode, Mode::sbrc);
    EXPECT_EQ(choice->slices, 64);
    EXPECT_DOUBLE_EQ(choice->psnr, 23.0);  // mean over the two volumes
    EXPECT_DOUBLE_EQ(choice->estimated_ms, 90.0);
    EXPECT_TRUE(choice->fits);
    EXPECT_EQ(choose_quality(table(), 1000.0, 256, 256)->mode, Mode::reference);
}

TEST(ChooseQuality, ScalesMeasuredTimesByPixelCount) {
    // At 512x512 every frame costs four times as much: 100 ms now fits only phong (4 x 50 = 200
    // does not fit; nothing does), so the fastest setting is returned, marked as not fitting.
    auto choice = choose_quality(table(), 100.0, 512, 512);
    ASSERT_TRUE(choice.has_value());
    EXPECT_FALSE(choice->fits);
    EXPECT_EQ(choice->mode, Mode::phong);
    EXPECT_EQ(choose_quality(table(), 400.0, 512, 512)->slices, 64);
}

TEST(ChooseQuality, EmptyTableChoosesNothingAndApplyChangesOnlyTheChosenFields) {
    EXPECT_FALSE(choose_quality({}, 100.0, 256, 256).has_value());
    FrameRequest request;
    request.settings.light_buffer.compensation = 2.0;
    const FrameRequest applied =
            apply_quality(request, {Mode::sbrc_cone, 32, 64, 1.0 / 128, 10.0, 20.0, true});
    EXPECT_EQ(applied.settings.mode, Mode::sbrc_cone);
    EXPECT_EQ(applied.settings.light_buffer.slices, 32);
    EXPECT_EQ(applied.settings.light_buffer.resolution, 64);
    EXPECT_DOUBLE_EQ(applied.settings.sample_distance, 1.0 / 128);
    EXPECT_DOUBLE_EQ(applied.settings.light_buffer.compensation, 2.0);
}

}  // namespace
}  // namespace penumbra::scene
