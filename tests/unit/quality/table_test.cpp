// The one rule that chooses a setting for a frame budget (table.hpp).

#include <penumbra/quality/table.hpp>

#include <gtest/gtest.h>

#include <string>

namespace penumbra::quality {
namespace {

Point point(const std::string& volume, scene::Mode mode, int slices, double frame_ms,
            double psnr_truth, double ssim_truth = 0.9) {
    Point p;
    p.volume = volume;
    p.light = {10.0, 45.0};
    p.mode = mode;
    p.slices = slices;
    p.resolution = slices > 0 ? 128 : 0;
    p.sample_distance = 1.0 / 256;
    p.frame_ms = frame_ms;
    p.psnr = psnr_truth;
    p.psnr_truth = psnr_truth;
    p.ssim = ssim_truth;
    p.ssim_truth = ssim_truth;
    return p;
}

// Two volumes measured at 256x256; the slowest frame of a setting decides whether it fits.
Table table() {
    Table t;
    t.width = 256;
    t.height = 256;
    t.points = {
            point("a", scene::Mode::phong, 0, 40.0, 18.0),
            point("b", scene::Mode::phong, 0, 50.0, 18.4),
            point("a", scene::Mode::sbrc, 64, 60.0, 22.0),
            point("b", scene::Mode::sbrc, 64, 90.0, 24.0),
            point("a", scene::Mode::sbrc, 256, 150.0, 28.0),
            point("b", scene::Mode::sbrc, 256, 120.0, 29.0),
            point("a", scene::Mode::reference, 0, 400.0, infinity, 1.0),
            point("b", scene::Mode::reference, 0, 380.0, infinity, 1.0),
    };
    return t;
}

TEST(Choose, PicksTheMostAccurateSettingWhoseSlowestFrameFits) {
    auto choice = choose(table(), 100.0, 256, 256);
    ASSERT_TRUE(choice.has_value());
    EXPECT_EQ(choice->setting.key.mode, scene::Mode::sbrc);
    EXPECT_EQ(choice->setting.key.slices, 64);
    EXPECT_DOUBLE_EQ(choice->setting.psnr_truth, 23.0);  // mean over the two volumes
    EXPECT_DOUBLE_EQ(choice->estimated_ms, 90.0);        // the slower volume
    EXPECT_TRUE(choice->fits);
    // 120 ms on b, but 150 on a: the slowest must fit.
    EXPECT_EQ(choose(table(), 140.0, 256, 256)->setting.key.slices, 64);
    EXPECT_EQ(choose(table(), 150.0, 256, 256)->setting.key.slices, 256);
    EXPECT_EQ(choose(table(), 1000.0, 256, 256)->setting.key.mode, scene::Mode::reference);
}

TEST(Choose, ScalesMeasuredTimesByPixelCount) {
    // At 512x512 every frame costs four times as much: nothing fits 100 ms, so the fastest
    // setting is returned, marked as not fitting.
    auto choice = choose(table(), 100.0, 512, 512);
    ASSERT_TRUE(choice.has_value());
    EXPECT_FALSE(choice->fits);
    EXPECT_EQ(choice->setting.key.mode, scene::Mode::phong);
    EXPECT_DOUBLE_EQ(choice->estimated_ms, 200.0);
    EXPECT_EQ(choose(table(), 400.0, 512, 512)->setting.key.slices, 64);
    EXPECT_NE(choice->describe(100.0).find("nothing measured fits"), std::string::npos);
}

TEST(Choose, OnlySettingsMeasuredOnEveryViewCompete) {
    Table t = table();
    // Fast and accurate, but measured on one volume only: its mean would be over a subset.
    t.points.push_back(point("a", scene::Mode::sbrc_cone, 64, 10.0, 40.0));
    EXPECT_EQ(choose(t, 100.0, 256, 256)->setting.key.mode, scene::Mode::sbrc);
    EXPECT_EQ(candidates(t.points).size(), 4u);
}

TEST(Choose, SsimDecidesBetweenEqualPsnrThenTheFaster) {
    Table t;
    t.width = t.height = 64;
    t.points = {point("a", scene::Mode::sbrc, 64, 30.0, 25.0, 0.90),
                point("a", scene::Mode::sbrc_cone, 64, 40.0, 25.0, 0.95),
                point("a", scene::Mode::sbrc_shell, 64, 20.0, 25.0, 0.95)};
    EXPECT_EQ(choose(t, 100.0, 64, 64)->setting.key.mode, scene::Mode::sbrc_shell);
    EXPECT_EQ(choose(t, 35.0, 64, 64)->setting.key.mode, scene::Mode::sbrc_shell);
    EXPECT_EQ(choose(t, 19.0, 64, 64)->setting.key.mode, scene::Mode::sbrc_shell);
    EXPECT_FALSE(choose(t, 19.0, 64, 64)->fits);
    t.points.pop_back();
    EXPECT_EQ(choose(t, 100.0, 64, 64)->setting.key.mode, scene::Mode::sbrc_cone);
}

TEST(Choose, AnExactImageRanksAboveEveryApproximateOne) {
    // Infinite PSNR is not capped: no finite figure, however high, beats the reference.
    Table t;
    t.width = t.height = 64;
    t.points = {point("a", scene::Mode::sbrc, 64, 30.0, 120.0, 1.0),
                point("a", scene::Mode::reference, 0, 50.0, infinity, 1.0)};
    EXPECT_EQ(choose(t, 100.0, 64, 64)->setting.key.mode, scene::Mode::reference);
}

TEST(Choose, AnEmptyTableChoosesNothing) {
    EXPECT_FALSE(choose(Table{}, 100.0, 256, 256).has_value());
}

TEST(Apply, ChangesOnlyTheChosenFields) {
    scene::FrameRequest request;
    request.settings.light_buffer.compensation = 2.0;
    request.settings.light_buffer.slices = 99;
    const scene::FrameRequest applied = apply(request, {scene::Mode::sbrc_cone, 32, 64, 1.0 / 128});
    EXPECT_EQ(applied.settings.mode, scene::Mode::sbrc_cone);
    EXPECT_EQ(applied.settings.light_buffer.slices, 32);
    EXPECT_EQ(applied.settings.light_buffer.resolution, 64);
    EXPECT_DOUBLE_EQ(applied.settings.sample_distance, 1.0 / 128);
    EXPECT_DOUBLE_EQ(applied.settings.light_buffer.compensation, 2.0);
    // A mode without slices keeps the request's.
    EXPECT_EQ(apply(request, {scene::Mode::phong, 0, 0, 1.0 / 256}).settings.light_buffer.slices,
              99);
}

TEST(Presets, AreTheChoiceAtTheTablesOwnSizeAndNothingWhereNothingFits) {
    const Table t = table();
    const auto presets = choose_presets(t, {10.0, 100.0, 1000.0});
    ASSERT_EQ(presets.size(), 3u);
    EXPECT_FALSE(presets[0].setting.has_value());
    ASSERT_TRUE(presets[1].setting.has_value());
    EXPECT_EQ(presets[1].setting->key, choose(t, 100.0, 256, 256)->setting.key);
    EXPECT_EQ(presets[2].setting->key.mode, scene::Mode::reference);
}

TEST(Presets, DefaultBudgetsRunFromTheFastestToTheReference) {
    const auto budgets = default_budgets(table().points);
    ASSERT_FALSE(budgets.empty());
    EXPECT_GE(budgets.front(), 50.0);
    EXPECT_LT(budgets.front(), 60.0);
    EXPECT_GE(budgets.back(), 400.0);
    for (std::size_t i = 1; i < budgets.size(); ++i) {
        EXPECT_GT(budgets[i], budgets[i - 1]);
    }
}

// Skipping is part of a setting: measured apart, chosen apart, applied with it.
TEST(Choose, SkippingIsASettingOfItsOwn) {
    Table t = table();
    for (Point p : table().points) {
        if (p.mode == scene::Mode::sbrc && p.slices == 64) {
            p.empty_space_skipping = false;  // the same image, slower
            p.frame_ms *= 2.0;
            t.points.push_back(p);
        }
    }
    // Without skipping n=64 takes 180 ms: it competes (5 candidates), but only with skipping
    // does it fit.
    EXPECT_EQ(candidates(t.points).size(), 5u);
    for (const double budget : {100.0, 140.0}) {
        const auto choice = choose(t, budget, 256, 256);
        ASSERT_TRUE(choice.has_value());
        EXPECT_EQ(choice->setting.key.slices, 64);
        EXPECT_TRUE(choice->setting.key.empty_space_skipping) << budget;
    }
    SettingKey key{scene::Mode::sbrc, 64, 128, 1.0 / 512};
    key.empty_space_skipping = false;
    scene::FrameRequest request;
    request.settings.empty_space_skipping = true;
    request.settings.jitter = true;
    const scene::FrameRequest applied = apply(request, key);
    EXPECT_FALSE(applied.settings.empty_space_skipping);
    EXPECT_TRUE(applied.settings.jitter);  // the viewer's, whatever the setting
    Setting chosen;
    chosen.key = key;
    const Choice choice{chosen, 10.0, true};
    EXPECT_NE(choice.describe(50.0).find("no skipping"), std::string::npos);
}

// A refined image takes its still and every step to arrive: a budget covers each frame, so it
// chooses the frame's setting, never a refined image, however accurate and fast per step; and
// jitter, which costs no time, stays the viewer's choice.
TEST(Choose, AJitteredOrRefinedImageIsNeverChosen) {
    Table t = table();
    for (Point p : table().points) {
        if (p.mode == scene::Mode::sbrc && p.slices == 64) {
            p.jitter = true;
            p.psnr_truth = 30.0;
            t.points.push_back(p);
            p.refinement_steps = 8;
            p.psnr_truth = 35.0;
            t.points.push_back(p);
        }
    }
    for (const Setting& s : candidates(t.points)) {
        EXPECT_FALSE(s.key.jitter);
        EXPECT_EQ(s.key.refinement_steps, 0);
    }
    EXPECT_EQ(candidates(t.points).size(), 4u);
    const auto choice = choose(t, 100.0, 256, 256);
    ASSERT_TRUE(choice.has_value());
    EXPECT_EQ(choice->setting.key.refinement_steps, 0);
    EXPECT_DOUBLE_EQ(choice->setting.psnr_truth, 23.0);
    EXPECT_EQ(default_budgets(t.points), default_budgets(table().points));
}

}  // namespace
}  // namespace penumbra::quality
