// Where `penumbra serve` gets its accuracy table: the order of the sources, the cache, and what
// is an error and what is only a note.

#include <penumbra/quality/startup.hpp>
#include <penumbra/quality/table_json.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace penumbra::quality {
namespace {

Table table_of(scene::Mode mode) {
    Table t;
    t.width = t.height = 64;
    Point p;
    p.volume = "ch2";
    p.mode = mode;
    p.sample_distance = 1.0 / 256;
    p.frame_ms = 10.0;
    p.psnr_truth = 30.0;
    t.points = {p};
    return t;
}

class ServeTableTest : public ::testing::Test {
protected:
    void SetUp() override {
        // One folder per process: CTest runs each test of this fixture in a process of its own,
        // side by side.
        folder_ = std::filesystem::path(::testing::TempDir()) /
                  ("penumbra_serve_table_test_" + std::to_string(::getpid()));
        std::filesystem::remove_all(folder_);
        std::filesystem::create_directories(folder_);
        paths_.committed = folder_ / "llvmpipe.json";
        paths_.cache = folder_ / "cache" / "quality-x.json";
    }

    void TearDown() override { std::filesystem::remove_all(folder_); }

    static void write(const std::filesystem::path& path, const Table& table) {
        ASSERT_TRUE(write_table_file(path, table, {}, "test").ok());
    }

    static void write_text(const std::filesystem::path& path, const std::string& text) {
        std::filesystem::create_directories(path.parent_path());
        std::ofstream(path) << text;
    }

    static scene::Mode mode_of(const ServeTable& served) {
        return served.table->points.front().mode;
    }

    std::filesystem::path folder_;
    TablePaths paths_;
};

TEST_F(ServeTableTest, AGivenTableComesFirstAndMustBeReadable) {
    write(paths_.committed, table_of(scene::Mode::phong));
    write(folder_ / "given.json", table_of(scene::Mode::sbrc));
    auto served = serve_table(folder_ / "given.json", {}, paths_);
    ASSERT_TRUE(served.ok()) << served.error().to_string();
    EXPECT_EQ(mode_of(*served), scene::Mode::sbrc);
    EXPECT_FALSE(serve_table(folder_ / "missing.json", {}, paths_).ok());
    write_text(folder_ / "bad.json", "{}");
    EXPECT_EQ(serve_table(folder_ / "bad.json", {}, paths_).error().code,
              base::ErrorCode::invalid_table);
}

TEST_F(ServeTableTest, AMeasuredTableIsServedAndCachedWithoutATextRoundTrip) {
    write(paths_.committed, table_of(scene::Mode::phong));
    StartupMeasurement measured;
    measured.volume = "ch2";
    measured.table = StartupTable{table_of(scene::Mode::sbrc_cone), true, 1.0};
    auto served = serve_table(std::nullopt, measured, paths_);
    ASSERT_TRUE(served.ok()) << served.error().to_string();
    EXPECT_EQ(mode_of(*served), scene::Mode::sbrc_cone);
    auto cached = read_table_file(*paths_.cache);
    ASSERT_TRUE(cached.ok()) << cached.error().to_string();
    EXPECT_EQ(cached->points.front().mode, scene::Mode::sbrc_cone);
}

TEST_F(ServeTableTest, TheCommittedTableComesBeforeTheCachedOne) {
    write(*paths_.cache, table_of(scene::Mode::sbrc));
    auto from_cache = serve_table(std::nullopt, {}, paths_);
    ASSERT_TRUE(from_cache.ok());
    EXPECT_EQ(mode_of(*from_cache), scene::Mode::sbrc);
    write(paths_.committed, table_of(scene::Mode::phong));
    auto committed = serve_table(std::nullopt, {}, paths_);
    ASSERT_TRUE(committed.ok());
    EXPECT_EQ(mode_of(*committed), scene::Mode::phong);
}

TEST_F(ServeTableTest, ABadCacheIsIgnoredButABadCommittedTableIsAnError) {
    write_text(*paths_.cache, "not json");
    auto served = serve_table(std::nullopt, {}, paths_);
    ASSERT_TRUE(served.ok());
    EXPECT_EQ(served->table, nullptr);
    ASSERT_FALSE(served->notes.empty());
    EXPECT_NE(served->notes.back().find("ignoring the cached table"), std::string::npos);
    write_text(paths_.committed, "not json");
    EXPECT_FALSE(serve_table(std::nullopt, {}, paths_).ok());
}

TEST_F(ServeTableTest, NoTableAnywhereServesWithoutBudgets) {
    StartupMeasurement failed;
    failed.error =
            base::make_error(base::ErrorCode::no_volume, "no volume to measure on", "--data");
    auto served = serve_table(std::nullopt, failed, paths_);
    ASSERT_TRUE(served.ok());
    EXPECT_EQ(served->table, nullptr);
    ASSERT_EQ(served->notes.size(), 2u);
    EXPECT_NE(served->notes[0].find("no volume to measure on"), std::string::npos);
    EXPECT_NE(served->notes[1].find("frame budgets are ignored"), std::string::npos);
}

TEST_F(ServeTableTest, MeasuresOnlyWhereAskedOrNothingExists) {
    EXPECT_TRUE(should_measure(Measure::where_missing, paths_));
    EXPECT_FALSE(should_measure(Measure::never, paths_));
    write(*paths_.cache, table_of(scene::Mode::sbrc));
    EXPECT_FALSE(should_measure(Measure::where_missing, paths_));
    EXPECT_TRUE(should_measure(Measure::always, paths_));
}

TEST(TablePaths, TheCacheIsOneFilePerRendererInTheCacheFolder) {
    render::RendererInfo info;
    info.renderer = "llvmpipe (LLVM 15.0.6, 256 bits)";
    info.gpu_timer_queries = false;
    const TablePaths paths = table_paths(info, "/x/penumbra");
    ASSERT_TRUE(paths.cache.has_value());
    EXPECT_EQ(*paths.cache, "/x/penumbra/quality-llvmpipe_LLVM_15.0.6_256_bits.json");
    EXPECT_EQ(paths.committed.filename(), "llvmpipe.json");
    EXPECT_FALSE(table_paths(info, std::nullopt).cache.has_value());
    info.gpu_timer_queries = true;
    EXPECT_EQ(table_paths(info, std::nullopt).committed.filename(), "gpu.json");
}

// A renderer for the start-up policy's paths that render nothing.
class IdleRenderer final : public render::FrameRenderer {
public:
    [[nodiscard]] const render::RendererInfo& info() const override { return info_; }

    base::Status set_volume(std::shared_ptr<const volume::Volume>) override { return base::Ok{}; }

    base::Result<render::Frame> render(const scene::FrameRequest&,
                                       const render::CancelPredicate&) override {
        ++frames;
        return base::make_error(base::ErrorCode::gl_unavailable, "not a renderer");
    }

    [[nodiscard]] std::size_t gpu_bytes_held() const override { return 0; }

    int frames = 0;

private:
    render::RendererInfo info_;
};

TEST(MeasureAtStartup, MeasuresNothingWhenToldNever) {
    IdleRenderer renderer;
    bool asked = false;
    const OfferedVolumes volumes{[] { return std::vector<std::string>{"ch2.nii.gz"}; },
                                 [&](const std::string&) {
                                     asked = true;
                                     return base::Result<std::shared_ptr<const volume::Volume>>(
                                             base::make_error(base::ErrorCode::not_found, "none"));
                                 }};
    const StartupMeasurement measured =
            measure_at_startup(renderer, Measure::never, volumes, {}, stdout);
    EXPECT_FALSE(measured.table.has_value());
    EXPECT_FALSE(measured.error.has_value());
    EXPECT_FALSE(asked);
    EXPECT_EQ(renderer.frames, 0);
}

TEST(MeasureAtStartup, ReportsWhyWithoutAVolumeOrWhenTheVolumeFailsToLoad) {
    IdleRenderer renderer;
    const auto failing = [](const std::string& id) {
        return base::Result<std::shared_ptr<const volume::Volume>>(
                base::make_error(base::ErrorCode::not_found, "cannot read " + id));
    };
    const StartupMeasurement none =
            measure_at_startup(renderer, Measure::always,
                               {[] { return std::vector<std::string>{}; }, failing}, {}, stdout);
    ASSERT_TRUE(none.error.has_value());
    EXPECT_EQ(none.error->code, base::ErrorCode::no_volume);
    const StartupMeasurement unreadable =
            measure_at_startup(renderer, Measure::always,
                               {[] {
                                    return std::vector<std::string>{"a.nii", "ch2.nii.gz"};
                                },
                                failing},
                               {}, stdout);
    ASSERT_TRUE(unreadable.error.has_value());
    EXPECT_EQ(unreadable.error->message, "cannot read ch2.nii.gz");
    EXPECT_FALSE(unreadable.table.has_value());
    EXPECT_EQ(renderer.frames, 0);
}

TEST(StartupVolume, IsCh2WhereOfferedElseTheFirst) {
    EXPECT_EQ(startup_volume({"a.nii", "ch2.nii.gz"}), "ch2.nii.gz");
    EXPECT_EQ(startup_volume({"a.nii", "b.nii"}), "a.nii");
    EXPECT_FALSE(startup_volume({}).has_value());
}

}  // namespace
}  // namespace penumbra::quality
