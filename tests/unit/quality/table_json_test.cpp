// The accuracy table's file form: written and read back unchanged, the committed tables read, a
// malformed table refused with the member it is about.

#include <penumbra/quality/table_json.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace penumbra::quality {
namespace {

Table sample_table() {
    Table t;
    t.device = "llvmpipe (LLVM 15.0.6, 256 bits)";
    t.vendor = "Mesa";
    t.gl_version = "4.5";
    t.width = 64;
    t.height = 48;
    t.repeat = 3;
    t.transfer_function = "mri_skin";
    t.compositing = "alpha";
    t.stage = "compute";
    t.builder = "multi_slice";
    t.light_lookup = "local";
    t.slab_samples = 0;
    t.camera = scene::orbit_camera(30.0, 20.0, 2.4);
    t.truth = TruthMethod{1.0 / 1024, 16};
    Point reference;
    reference.volume = "ch2";
    reference.light = {10.0, 45.0};
    reference.mode = scene::Mode::reference;
    reference.sample_distance = 1.0 / 256;
    reference.frame_ms = 400.5;
    reference.psnr = infinity;
    reference.psnr_truth = infinity;
    reference.empty_space_skipping = false;
    Point sbrc = reference;
    sbrc.empty_space_skipping = true;
    sbrc.jitter = true;
    sbrc.refinement_steps = 4;
    sbrc.mode = scene::Mode::sbrc;
    sbrc.slices = 64;
    sbrc.resolution = 128;
    sbrc.frame_ms = 40.25;
    sbrc.light_buffer_ms = 12.5;
    sbrc.rmse = 0.01;
    sbrc.psnr = 30.5;
    sbrc.ssim = 0.97;
    sbrc.rmse_truth = 0.02;
    sbrc.psnr_truth = 28.0;
    sbrc.ssim_truth = 0.95;
    t.points = {reference, sbrc};
    return t;
}

TEST(TableJson, RoundTripsEveryField) {
    const Table t = sample_table();
    auto read = parse_table(table_json(t, choose_presets(t, {50.0, 500.0})), "t.json");
    ASSERT_TRUE(read.ok()) << read.error().to_string();
    EXPECT_EQ(read->device, t.device);
    EXPECT_EQ(read->vendor, t.vendor);
    EXPECT_EQ(read->gl_version, t.gl_version);
    EXPECT_EQ(read->gpu_timers, t.gpu_timers);
    EXPECT_EQ(read->width, 64);
    EXPECT_EQ(read->height, 48);
    EXPECT_EQ(read->repeat, 3);
    EXPECT_EQ(read->transfer_function, t.transfer_function);
    EXPECT_EQ(read->compositing, t.compositing);
    EXPECT_EQ(read->stage, t.stage);
    EXPECT_EQ(read->builder, t.builder);
    EXPECT_EQ(read->light_lookup, t.light_lookup);
    EXPECT_EQ(read->slab_samples, t.slab_samples);
    EXPECT_EQ(read->phong, t.phong);
    EXPECT_EQ(read->camera.eye, t.camera.eye);
    EXPECT_EQ(read->camera.up, t.camera.up);
    EXPECT_DOUBLE_EQ(read->camera.fov_y_degrees, t.camera.fov_y_degrees);
    EXPECT_EQ(read->truth, t.truth);
    ASSERT_EQ(read->points.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
        const Point& a = read->points[i];
        const Point& b = t.points[i];
        EXPECT_EQ(a.volume, b.volume);
        EXPECT_EQ(a.light, b.light);
        EXPECT_EQ(a.mode, b.mode);
        EXPECT_EQ(a.slices, b.slices);
        EXPECT_EQ(a.resolution, b.resolution);
        EXPECT_DOUBLE_EQ(a.sample_distance, b.sample_distance);
        EXPECT_EQ(a.empty_space_skipping, b.empty_space_skipping);
        EXPECT_EQ(a.jitter, b.jitter);
        EXPECT_EQ(a.refinement_steps, b.refinement_steps);
        EXPECT_DOUBLE_EQ(a.frame_ms, b.frame_ms);
        EXPECT_DOUBLE_EQ(a.light_buffer_ms, b.light_buffer_ms);
        EXPECT_DOUBLE_EQ(a.rmse, b.rmse);
        EXPECT_EQ(a.psnr, b.psnr);  // infinite stays infinite
        EXPECT_DOUBLE_EQ(a.ssim, b.ssim);
        EXPECT_DOUBLE_EQ(a.rmse_truth, b.rmse_truth);
        EXPECT_EQ(a.psnr_truth, b.psnr_truth);
        EXPECT_DOUBLE_EQ(a.ssim_truth, b.ssim_truth);
    }
    // Written again, the same text.
    EXPECT_EQ(table_json(*read, {}), table_json(t, {}));
}

TEST(TableJson, WritesThroughARenameAndReadsTheFileBack) {
    const std::filesystem::path folder =
            std::filesystem::path(::testing::TempDir()) / "penumbra_table_json_test";
    std::filesystem::remove_all(folder);
    const std::filesystem::path path = folder / "sub" / "table.json";
    ASSERT_TRUE(write_table_file(path, sample_table(), {}, "test").ok());
    EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
    auto read = read_table_file(path);
    ASSERT_TRUE(read.ok()) << read.error().to_string();
    EXPECT_EQ(read->points.size(), 2u);
    std::filesystem::remove_all(folder);
    auto missing = read_table_file(path);
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().code, base::ErrorCode::not_found);
}

TEST(TableJson, ReadsTheCommittedTables) {
    int read_count = 0;
    for (const auto& entry : std::filesystem::directory_iterator(PENUMBRA_ACCURACY_DIR)) {
        if (entry.path().extension() != ".json") {
            continue;
        }
        auto table = read_table_file(entry.path());
        ASSERT_TRUE(table.ok()) << table.error().to_string();
        EXPECT_GT(table->points.size(), 10u) << entry.path();
        EXPECT_TRUE(choose(*table, 1e9, table->width, table->height).has_value());
        ++read_count;
    }
    EXPECT_GE(read_count, 1);
}

// Replaces the first `from` in the sample table's text with `to`, and parses it.
base::Result<Table> parse_edited(const std::string& from, const std::string& to) {
    std::string text = table_json(sample_table(), {});
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    return parse_table(text, "t.json");
}

void expect_refused(const base::Result<Table>& table, const std::string& where,
                    const std::string& message_part) {
    ASSERT_FALSE(table.ok());
    EXPECT_EQ(table.error().code, base::ErrorCode::invalid_table);
    EXPECT_EQ(table.error().where, where);
    EXPECT_NE(table.error().message.find(message_part), std::string::npos) << table.error().message;
}

TEST(TableJson, AMalformedTableIsRefusedNamingTheMember) {
    expect_refused(parse_table("{", "t.json"), "t.json", "not JSON");
    expect_refused(parse_table("[]", "t.json"), "t.json/format", "not an accuracy table");
    expect_refused(parse_edited("\"penumbra-accuracy-1\"", "\"other\""), "t.json/format",
                   "not an accuracy table");
    expect_refused(parse_edited("\"frame_ms\": 40.25", "\"frame_ms\": \"fast\""),
                   "t.json/points/1/frame_ms", "expected a finite number");
    expect_refused(parse_edited("\"slices\": 64", "\"slices\": -1"), "t.json/points/1/slices",
                   "expected an integer");
    expect_refused(parse_edited("\"frame_ms\": 40.25,", ""), "t.json/points/1/frame_ms",
                   "missing 'frame_ms'");
    expect_refused(parse_edited("\"size\": [\n  64,\n  48\n ]", "\"size\": [64]"), "t.json/size",
                   "expected an array");
    expect_refused(parse_edited("\"phong\": true", "\"phong\": 1"), "t.json/settings/phong",
                   "expected true or false");
    expect_refused(parse_table(std::string(100, '[') + std::string(100, ']'), "t.json"), "t.json",
                   "nested deeper");
}

// A table written before skipping, jitter and refinement existed was measured without them.
TEST(TableJson, PointsWithoutSkippingJitterOrRefinementWereMeasuredWithoutThem) {
    std::string text = table_json(sample_table(), {});
    for (const std::string member :
         {"\"empty_space_skipping\": true,", "\"empty_space_skipping\": false,",
          "\"jitter\": true,", "\"jitter\": false,", "\"refinement_steps\": 4,",
          "\"refinement_steps\": 0,"}) {
        const auto at = text.find(member);
        ASSERT_NE(at, std::string::npos) << member;
        text.erase(at, member.size());
    }
    auto table = parse_table(text, "t.json");
    ASSERT_TRUE(table.ok()) << table.error().to_string();
    for (const Point& p : table->points) {
        EXPECT_FALSE(p.empty_space_skipping);
        EXPECT_FALSE(p.jitter);
        EXPECT_EQ(p.refinement_steps, 0);
    }
}

// A table written before the converged truth compared with the finest reference swept, under
// the names *_finest: that reference was its truth.
TEST(TableJson, ATableWithoutATruthComparedWithTheFinestReference) {
    Table t = sample_table();
    t.truth.reset();
    std::string text = table_json(t, {});
    const std::string no_truth = ",\n  \"truth\": null";
    const auto at = text.find(no_truth);
    ASSERT_NE(at, std::string::npos);
    text.erase(at, no_truth.size());
    for (const std::string name : {"rmse", "psnr", "ssim"}) {
        for (auto found = text.find(name + "_truth"); found != std::string::npos;
             found = text.find(name + "_truth")) {
            text.replace(found, name.size() + 6, name + "_finest");
        }
    }
    auto read = parse_table(text, "t.json");
    ASSERT_TRUE(read.ok()) << read.error().to_string();
    EXPECT_FALSE(read->truth.has_value());
    ASSERT_EQ(read->points.size(), 2u);
    EXPECT_EQ(read->points[1].psnr_truth, 28.0);
    EXPECT_EQ(read->points[1].ssim_truth, 0.95);
    EXPECT_TRUE(std::isinf(read->points[0].psnr_truth));
}

TEST(TableJson, ATruthOfNoDistanceOrOneFrameIsRefused) {
    expect_refused(parse_edited("\"sample_distance\": 0.0009765625", "\"sample_distance\": 0"),
                   "t.json/settings/truth/sample_distance", "expected a positive number");
    expect_refused(parse_edited("\"frames\": 16", "\"frames\": 0"), "t.json/settings/truth/frames",
                   "expected an integer of at least 1");
}

TEST(TableJson, RefinementStepsWithoutJitterAreRefused) {
    expect_refused(parse_edited("\"jitter\": true", "\"jitter\": false"),
                   "t.json/points/1/refinement_steps", "expected jitter true");
    expect_refused(parse_edited("\"refinement_steps\": 4", "\"refinement_steps\": 100000"),
                   "t.json/points/1/refinement_steps", "at most");
    expect_refused(parse_edited("\"jitter\": true", "\"jitter\": 1"), "t.json/points/1/jitter",
                   "expected true or false");
}

TEST(TableJson, PointsOfAnUnknownModeAreSkipped) {
    auto table = parse_edited("\"mode\": \"sbrc\"", "\"mode\": \"a_future_mode\"");
    ASSERT_TRUE(table.ok()) << table.error().to_string();
    ASSERT_EQ(table->points.size(), 1u);
    EXPECT_EQ(table->points.front().mode, scene::Mode::reference);
}

}  // namespace
}  // namespace penumbra::quality
