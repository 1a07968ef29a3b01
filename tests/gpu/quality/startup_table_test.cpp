// The short accuracy table `penumbra serve` measures at start-up where no table exists for the
// device: the same sweep code as `bench accuracy`, at a tiny size, its JSON written and read back
// as the server's cache is, and the server's choice from it.

#include "synthetic_volumes.hpp"

#include <penumbra/quality/startup.hpp>
#include <penumbra/quality/table_json.hpp>
#include <penumbra/render/renderer.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <tuple>

namespace penumbra::quality {
namespace {

// The start-up sweep cut down to a few slices and texels, so llvmpipe measures it in seconds.
StartupOptions tiny_options() {
    StartupOptions options = startup_options();
    options.side = 32;
    options.time_limit_s = 600.0;
    options.sweep.slices = {8, 16};
    options.sweep.resolutions = {16, 32};
    options.sweep.half_angle_slices = {8, 16};
    options.sweep.half_angle_resolutions = {16};
    options.sweep.repeat = 1;
    return options;
}

// A view of the whole volume with a transfer function that shows its inside.
scene::FrameRequest frame() {
    scene::FrameRequest request;
    request.camera = scene::orbit_camera(30.0, 20.0, 2.4);
    request.transfer_function = {
            "test",
            {{0.0, {0.2, 0.4, 1.0}}, {0.5, {1.0, 0.6, 0.2}}, {1.0, {1.0, 1.0, 1.0}}},
            {{0.0, 0.0}, {0.2, 0.0}, {0.6, 0.1}, {1.0, 0.6}}};
    return request;
}

class StartupTableTest : public ::testing::Test {
protected:
    void SetUp() override {
        auto created = render::Renderer::create();
        ASSERT_TRUE(created.ok()) << created.error().to_string();
        renderer_ = std::move(created.value());
    }

    std::unique_ptr<render::Renderer> renderer_;
    std::shared_ptr<const volume::Volume> volume_ =
            std::make_shared<const volume::Volume>(test::radial_volume(16));
};

TEST(StartupOptions, AreTheShortSweep) {
    const StartupOptions options = startup_options();
    EXPECT_EQ(options.side, 256);
    EXPECT_EQ(options.sweep.modes,
              (std::vector<scene::Mode>{scene::Mode::phong, scene::Mode::half_angle,
                                        scene::Mode::sbrc, scene::Mode::sbrc_cone}));
    EXPECT_EQ(options.sweep.slices, (std::vector<int>{64, 128, 256}));
    EXPECT_EQ(options.sweep.resolutions, (std::vector<int>{128, 256}));
    EXPECT_EQ(options.sweep.half_angle_slices, (std::vector<int>{64, 128}));
    ASSERT_EQ(options.sweep.lights.size(), 1u);
    EXPECT_EQ(options.sweep.lights.front(), (LightAngles{10.0, 45.0}));
    EXPECT_EQ(options.sweep.distances, (std::vector<double>{1.0 / 256.0}));
    EXPECT_EQ(options.sweep.repeat, 3);
    // One reference, phong, 2 half_angle, 6 each of sbrc and sbrc_cone.
    EXPECT_EQ(frames_per_view(options.sweep), (1u + 1u + 2u + 12u) * 4u + 6u * 4u);
}

TEST_F(StartupTableTest, MeasuresEveryModeAndRoundTripsThroughTheServersParser) {
    const StartupOptions options = tiny_options();
    auto measured = measure_startup_table(*renderer_, volume_, frame(), options);
    ASSERT_TRUE(measured.ok()) << measured.error().to_string();
    EXPECT_TRUE(measured->complete);
    EXPECT_GT(measured->seconds, 0.0);
    const Table& table = measured->table;
    EXPECT_EQ(table.width, 32);
    EXPECT_EQ(table.height, 32);
    EXPECT_EQ(table.device, renderer_->info().renderer);

    // reference + phong + half_angle at 2 n x 1 R + sbrc and sbrc_cone at 2 n x 2 R.
    ASSERT_EQ(table.points.size(), 1u + 1u + 2u + 4u + 4u);
    std::set<scene::Mode> modes;
    std::set<std::tuple<scene::Mode, int, int>> settings;
    for (const Point& p : table.points) {
        modes.insert(p.mode);
        settings.insert({p.mode, p.slices, p.resolution});
        EXPECT_GT(p.frame_ms, 0.0) << scene::to_string(p.mode);
        if (p.mode == scene::Mode::reference) {
            EXPECT_TRUE(std::isinf(p.psnr));
            EXPECT_TRUE(std::isinf(p.psnr_truth));
        } else {
            EXPECT_TRUE(std::isfinite(p.psnr)) << scene::to_string(p.mode);
        }
        if (p.mode == scene::Mode::half_angle) {
            EXPECT_EQ(p.resolution, 16) << "half_angle only at the resolutions asked for";
        }
        if (scene::uses_light_buffer(p.mode)) {
            EXPECT_GT(p.light_buffer_ms, 0.0) << scene::to_string(p.mode);
        }
    }
    EXPECT_EQ(settings.size(), table.points.size()) << "a setting measured twice";
    for (const scene::Mode mode : options.sweep.modes) {
        EXPECT_TRUE(modes.count(mode) == 1) << scene::to_string(mode) << " has no point";
    }
    EXPECT_TRUE(modes.count(scene::Mode::reference) == 1);

    const std::filesystem::path path =
            std::filesystem::path(::testing::TempDir()) / "penumbra_startup_table.json";
    ASSERT_TRUE(write_table_file(path, table, choose_presets(table, default_budgets(table.points)),
                                 "test")
                        .ok());
    auto read = read_table_file(path);
    ASSERT_TRUE(read.ok()) << read.error().to_string();
    ASSERT_EQ(read->points.size(), table.points.size());
    for (std::size_t i = 0; i < read->points.size(); ++i) {
        const Point& r = read->points[i];
        const Point& p = table.points[i];
        EXPECT_EQ(r.mode, p.mode);
        EXPECT_EQ(r.slices, p.slices);
        EXPECT_EQ(r.resolution, p.resolution);
        EXPECT_DOUBLE_EQ(r.frame_ms, p.frame_ms);
        EXPECT_EQ(std::isinf(r.psnr_truth), std::isinf(p.psnr_truth));
    }
    EXPECT_EQ(read->width, 32);
    EXPECT_EQ(read->camera.eye, table.camera.eye);
    std::filesystem::remove(path);

    // The server chooses from it: an unbounded budget gets the reference.
    auto choice = choose(*read, 1e9, 32, 32);
    ASSERT_TRUE(choice.has_value());
    EXPECT_EQ(choice->setting.key.mode, scene::Mode::reference);
}

// Start-up stays bounded: past the time limit the sweep stops after the point in hand and the
// server serves with what was measured.
TEST_F(StartupTableTest, StopsAtTheTimeLimitWithThePointsMeasured) {
    StartupOptions options = tiny_options();
    options.time_limit_s = 0.0;
    auto measured = measure_startup_table(*renderer_, volume_, frame(), options);
    ASSERT_TRUE(measured.ok()) << measured.error().to_string();
    EXPECT_FALSE(measured->complete);
    ASSERT_EQ(measured->table.points.size(), 1u);
    EXPECT_EQ(measured->table.points.front().mode, scene::Mode::reference);
}

TEST_F(StartupTableTest, RejectsFramesTooSmallForSsim) {
    StartupOptions options = tiny_options();
    options.side = min_image_side - 1;
    EXPECT_FALSE(measure_startup_table(*renderer_, volume_, frame(), options).ok());
}

// The sweep's switches on a real renderer: every setting with skipping on and off, jittered and
// refined points apart; skipping changes no image (the references agree exactly).
TEST_F(StartupTableTest, MeasuresSkippingJitterAndRefinementAsPointsOfTheirOwn) {
    Sweep sweep;
    sweep.modes = {scene::Mode::phong, scene::Mode::sbrc};
    sweep.slices = {8};
    sweep.resolutions = {16};
    sweep.distances = {1.0 / 64, 1.0 / 32};
    sweep.skipping = {true, false};
    sweep.jitter = {false, true};
    sweep.refinement_steps = {2, 4};
    sweep.repeat = 1;
    scene::FrameRequest base = frame();
    base.settings.width = base.settings.height = 32;
    base.settings.phong = true;
    ASSERT_TRUE(renderer_->set_volume(volume_).ok());
    AccuracyBench bench(*renderer_, sweep.repeat);
    std::vector<Point> points;
    auto measured = measure_view(
            bench, sweep, base, "radial", {10.0, 45.0}, [](const Point&) { return true; }, points);
    ASSERT_TRUE(measured.ok()) << measured.error().to_string();
    EXPECT_TRUE(*measured);
    EXPECT_EQ(bench.frames(), frames_per_view(sweep));
    // 2 distances x (2 references + 2 modes x 2 skipping x (1 unjittered + 1 jittered + 2
    // refined)).
    ASSERT_EQ(points.size(), 2u * (2u + 2u * 2u * 4u));
    std::set<std::tuple<scene::Mode, double, bool, bool, int>> settings;
    for (const Point& p : points) {
        settings.insert(
                {p.mode, p.sample_distance, p.empty_space_skipping, p.jitter, p.refinement_steps});
        EXPECT_GT(p.frame_ms, 0.0);
        EXPECT_TRUE(p.refinement_steps == 0 || p.jitter);
        if (p.mode == scene::Mode::reference) {
            EXPECT_FALSE(p.jitter);
            EXPECT_TRUE(std::isinf(p.psnr)) << "skipping " << p.empty_space_skipping;
        }
    }
    EXPECT_EQ(settings.size(), points.size()) << "a setting measured twice";
    // The same setting with and without skipping renders the same image.
    for (const Point& on : points) {
        for (const Point& off : points) {
            if (on.mode == off.mode && on.sample_distance == off.sample_distance &&
                on.jitter == off.jitter && on.refinement_steps == off.refinement_steps &&
                on.empty_space_skipping && !off.empty_space_skipping) {
                EXPECT_DOUBLE_EQ(on.psnr, off.psnr) << scene::to_string(on.mode);
            }
        }
    }
}

}  // namespace
}  // namespace penumbra::quality
