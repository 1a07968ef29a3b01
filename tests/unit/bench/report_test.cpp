// The accuracy table for people: labels, Pareto fronts and the plot script around the template.

#include <penumbra/bench/report.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace penumbra::bench {
namespace {

quality::Setting setting(scene::Mode mode, int slices, double ms, double psnr) {
    quality::Setting s;
    s.key = {mode, slices, slices > 0 ? 64 : 0, 1.0 / 256};
    s.count = 1;
    s.frame_ms = s.worst_frame_ms = ms;
    s.psnr_truth = psnr;
    return s;
}

TEST(Report, LabelsReadAsPeopleWriteThem) {
    EXPECT_EQ(distance_label(1.0 / 256), "1/256");
    EXPECT_EQ(distance_label(0.003), "0.003");
    EXPECT_EQ(psnr_text(quality::infinity), "inf");
    EXPECT_EQ(psnr_text(23.456), "23.46");
}

TEST(Report, TheParetoFrontDropsEverySettingBeatenInTimeAndAccuracy) {
    const auto front = pareto_front(
            {setting(scene::Mode::sbrc, 64, 30.0, 25.0),
             setting(scene::Mode::sbrc, 128, 40.0, 24.0),  // beaten
             setting(scene::Mode::dvr, 0, 10.0, 12.0), setting(scene::Mode::sbrc, 256, 60.0, 28.0)},
            false);
    ASSERT_EQ(front.size(), 3u);
    EXPECT_EQ(front[0].key.mode, scene::Mode::dvr);
    EXPECT_EQ(front[1].key.slices, 64);
    EXPECT_EQ(front[2].key.slices, 256);
}

TEST(Report, ThePlotScriptIsTheDataAndVariablesAboveTheTemplate) {
    quality::Table table;
    table.device = "test \"device\"";
    table.width = table.height = 64;
    quality::Point p;
    p.volume = "ch2";
    p.sample_distance = 1.0 / 256;
    for (const auto& [mode, ms, psnr] :
         {std::tuple{scene::Mode::sbrc, 30.0, 25.0}, std::tuple{scene::Mode::phong, 20.0, 18.0},
          std::tuple{scene::Mode::reference, 90.0, quality::infinity}}) {
        p.mode = mode;
        p.frame_ms = ms;
        p.psnr_truth = psnr;
        table.points.push_back(p);
    }
    const std::string script = plot_script(table, "a.png", "a.svg", "TEMPLATE\n");
    EXPECT_EQ(script.substr(script.size() - 9), "TEMPLATE\n");
    EXPECT_NE(script.find("png = \"a.png\""), std::string::npos);
    EXPECT_NE(script.find("panels = 1\n"), std::string::npos);
    EXPECT_NE(script.find("modes = \"phong sbrc\""), std::string::npos);
    EXPECT_NE(script.find("ref_count = 1\n"), std::string::npos);
    EXPECT_NE(script.find("test \\\"device\\\""), std::string::npos);  // quoted for gnuplot
    EXPECT_NE(script.find("$own << EOD\n1 1 20 18.0000\n1 2 30 25.0000\nEOD"), std::string::npos)
            << script;
}

// Settings that differ from the request's defaults are marked apart, by kind, and stay out of
// the modes' curves; a refined image sits at the time its still and steps take in all.
TEST(Report, VariantsAreMarkedApartFromTheModesCurves) {
    quality::Table table;
    table.width = table.height = 64;
    quality::Point p;
    p.volume = "ch2";
    p.sample_distance = 1.0 / 256;
    p.mode = scene::Mode::sbrc;
    p.frame_ms = 30.0;
    p.psnr_truth = 25.0;
    table.points.push_back(p);
    quality::Point off = p;
    off.empty_space_skipping = false;
    off.frame_ms = 60.0;
    table.points.push_back(off);
    quality::Point refined = p;
    refined.jitter = true;
    refined.refinement_steps = 3;
    refined.psnr_truth = 27.0;
    table.points.push_back(refined);
    quality::Point reference = off;
    reference.mode = scene::Mode::reference;
    reference.psnr_truth = quality::infinity;
    table.points.push_back(reference);
    const std::string script = plot_script(table, "a.png", "a.svg", "TEMPLATE\n");
    EXPECT_NE(script.find("$own << EOD\n1 1 30 25.0000\nEOD"), std::string::npos) << script;
    EXPECT_NE(script.find("$variants << EOD\n1 1 60 25.0000 1\n1 1 120 27.0000 3\nEOD"),
              std::string::npos)
            << script;
    EXPECT_NE(script.find("variant_kinds = \"1 3\""), std::string::npos);
    EXPECT_NE(script.find("reference 1/256 no skipping"), std::string::npos);
}

// gnuplot draws the template around a table with variants and one without (where every
// iteration over the variants is empty).
TEST(Report, GnuplotDrawsTablesWithAndWithoutVariants) {
    const std::filesystem::path folder =
            std::filesystem::path(::testing::TempDir()) / "penumbra_report_test";
    std::filesystem::create_directories(folder);
    quality::Table table;
    table.width = table.height = 64;
    quality::Point p;
    p.volume = "ch2";
    p.sample_distance = 1.0 / 256;
    p.mode = scene::Mode::sbrc;
    p.frame_ms = 30.0;
    p.psnr_truth = 25.0;
    table.points.push_back(p);
    p.mode = scene::Mode::reference;
    p.frame_ms = 90.0;
    p.psnr_truth = quality::infinity;
    table.points.push_back(p);
    for (const bool variants : {false, true}) {
        if (variants) {
            p.mode = scene::Mode::sbrc;
            p.jitter = true;
            p.refinement_steps = 4;
            p.psnr_truth = 27.0;
            table.points.push_back(p);
        }
        const std::filesystem::path png = folder / (variants ? "with.png" : "without.png");
        auto files = write_plot(table, png, "--plot");
        ASSERT_TRUE(files.ok()) << files.error().to_string();
        EXPECT_GT(std::filesystem::file_size(files->png), 0u);
        EXPECT_GT(std::filesystem::file_size(files->svg), 0u);
    }
    std::filesystem::remove_all(folder);
}

TEST(Report, ThePlotTemplateIsInstalledData) {
    auto text = read_plot_template();
    ASSERT_TRUE(text.ok()) << text.error().to_string();
    EXPECT_NE(text->find("set multiplot"), std::string::npos);
}

}  // namespace
}  // namespace penumbra::bench
