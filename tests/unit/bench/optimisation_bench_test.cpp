// The optimisation table's measuring, against a renderer whose pass times follow from the request:
// which series each row times, which of its passes, and which images it compares.

#include <penumbra/bench/optimisation_bench.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace penumbra::bench {
namespace {

// Ray casting costs 2 ms with empty-space skipping and 5 without, three times that with
// Blinn-Phong; a light-buffer build 7 ms with skipping and 9 without, only when the light moved;
// every frame also runs a 1 ms pass. Images are equal with and without skipping except in dvr,
// where one channel of one pixel differs by one.
class TimedRenderer final : public render::FrameRenderer {
public:
    TimedRenderer() { info_.gpu_timer_queries = false; }

    [[nodiscard]] const render::RendererInfo& info() const override { return info_; }

    base::Status set_volume(std::shared_ptr<const volume::Volume>) override { return base::Ok{}; }

    base::Result<render::Frame> render(const scene::FrameRequest& request,
                                       const render::CancelPredicate&) override {
        const scene::RenderSettings& s = request.settings;
        const bool skipping = s.empty_space_skipping;
        render::Frame frame;
        frame.report.passes.push_back({"tf_table", 0.0, 1.0});
        if (scene::uses_light_buffer(s.mode)) {
            const bool moved = !lit_ || request.light.direction != last_light_.direction ||
                               request.light.position != last_light_.position;
            frame.report.light_buffer =
                    moved ? render::LightBufferState::built : render::LightBufferState::reused;
            if (moved) {
                frame.report.passes.push_back(
                        {"light_buffer_" + std::string(scene::to_string(s.light_buffer.builder)),
                         0.0, skipping ? 7.0 : 9.0});
            }
            last_light_ = request.light;
            lit_ = true;
        }
        frame.report.passes.push_back(
                {"raycast", 0.0, (skipping ? 2.0 : 5.0) * (s.phong ? 3.0 : 1.0)});
        frame.image = base::ImageRgba8(4, 4);
        for (auto& value : frame.image.pixels) {
            value = 100;
        }
        if (s.mode == scene::Mode::dvr && !skipping) {
            frame.image.pixels[0] = 101;
        }
        return frame;
    }

    [[nodiscard]] std::size_t gpu_bytes_held() const override { return 0; }

private:
    render::RendererInfo info_;
    scene::Light last_light_;
    bool lit_ = false;
};

TEST(ModeBenchSeries, TimesTheWholeFrameAndTheNamedPassFromTheSameFrames) {
    TimedRenderer renderer;
    ModeBench bench(renderer, {}, 3);
    scene::FrameRequest request = bench.request(scene::Mode::phong, 0, 0);
    request.settings.phong = true;
    auto series = bench.measure_series({scene::Mode::phong, "frame", "", 0, 0, {}}, request,
                                       LightBufferUse::none, "raycast");
    ASSERT_TRUE(series) << series.error().to_string();
    EXPECT_DOUBLE_EQ(series->frame.wall_ms, 1.0 + 6.0);
    ASSERT_TRUE(series->pass);
    EXPECT_DOUBLE_EQ(series->pass->wall_ms, 6.0);
    EXPECT_FALSE(series->frame.gpu_ms);
    EXPECT_EQ(series->last_image.width, 4);
}

TEST(ModeBenchSeries, APassNoFrameRanIsRefused) {
    TimedRenderer renderer;
    ModeBench bench(renderer, {}, 1);
    auto series = bench.measure_series({scene::Mode::dvr, "frame", "", 0, 0, {}},
                                       bench.request(scene::Mode::dvr, 0, 0), LightBufferUse::none,
                                       "half_angle");
    ASSERT_FALSE(series);
    EXPECT_EQ(series.error().code, base::ErrorCode::bench_invalid);
}

TEST(OptimisationTable, EachRayCastModeWithSkippingOnAndOffThenTheBuildAndTheRatios) {
    TimedRenderer renderer;
    ModeBench bench(renderer, {}, 2);
    const std::vector<scene::Mode> modes = {scene::Mode::dvr, scene::Mode::half_angle,
                                            scene::Mode::phong, scene::Mode::sbrc};
    std::FILE* out = std::tmpfile();
    ASSERT_NE(out, nullptr);
    auto table = measure_optimisations(bench, modes, volume::Volume{}, out);
    std::fclose(out);
    ASSERT_TRUE(table) << table.error().to_string();

    std::vector<std::string> labels;
    for (const SkippingRow& row : table->rows) {
        labels.push_back(row.label);
        EXPECT_DOUBLE_EQ(row.on.frame.wall_ms, 1.0 + row.on.pass->wall_ms) << row.label;
    }
    EXPECT_EQ(labels,
              (std::vector<std::string>{"dvr", "phong", "sbrc cached", "sbrc cached, no phong"}));
    const SkippingRow& dvr = table->rows[0];
    EXPECT_DOUBLE_EQ(dvr.on.pass->wall_ms, 2.0);
    EXPECT_DOUBLE_EQ(dvr.off.pass->wall_ms, 5.0);
    EXPECT_TRUE(std::isfinite(dvr.psnr));
    // The shadow mode with Blinn-Phong, as the targets measure it, and once without.
    EXPECT_DOUBLE_EQ(table->rows[2].on.pass->wall_ms, 6.0);
    EXPECT_DOUBLE_EQ(table->rows[3].off.pass->wall_ms, 5.0);
    EXPECT_TRUE(std::isinf(table->rows[2].psnr));
    // The build alone, rebuilt every frame.
    ASSERT_TRUE(table->build_on && table->build_off);
    EXPECT_DOUBLE_EQ(table->build_on->wall_ms, 7.0);
    EXPECT_DOUBLE_EQ(table->build_off->wall_ms, 9.0);
}

}  // namespace
}  // namespace penumbra::bench
