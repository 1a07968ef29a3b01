#pragma once

// The accuracy table for people: its CSV, labels, Pareto fronts and the gnuplot script of
// `penumbra bench accuracy --plot` (its data and variables, written above the template
// share/penumbra/plots/accuracy.gp).

#include <penumbra/base/result.hpp>
#include <penumbra/quality/table.hpp>

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::bench {

// "inf" or "23.45".
std::string psnr_text(double psnr);

// 1/256 rather than 0.00390625 wherever a person reads it.
std::string distance_label(double distance);

// The settings no other setting beats in both time and accuracy, fastest first; by the slowest
// frame where `worst_time`, else by the mean.
std::vector<quality::Setting> pareto_front(std::vector<quality::Setting> settings, bool worst_time);

// One row per point; errors name `where`.
base::Status write_csv(const quality::Table& table, const std::filesystem::path& path,
                       const std::string& where);

// The plot template, from share/penumbra/plots.
base::Result<std::string> read_plot_template();

// The presets as `bench accuracy` prints them: a heading, then one row per budget.
std::string presets_text(const quality::Table& table, const std::vector<quality::Preset>& presets);

// The frame every point of the table shares, one line.
std::string frame_text(const quality::Table& table);

// The heading of one volume and light's rows, and one point's row under it.
std::string view_header(const std::string& volume, const quality::LightAngles& light);
std::string point_row(const quality::Point& p);

struct PlotFiles {
    std::filesystem::path png;
    std::filesystem::path svg;
    std::filesystem::path script;  // FILE.gp, redraws both in its folder
};

// Writes the gnuplot script beside `png` (naming the images without a folder, so that gnuplot
// run in that folder redraws them) and runs gnuplot there. Errors name `where`.
base::Result<PlotFiles> write_plot(const quality::Table& table, const std::filesystem::path& png,
                                   const std::string& where);

// A gnuplot script that draws `png` and `svg` (names in the folder it runs in): the table's data
// and the template's variables, then `plot_template`.
std::string plot_script(const quality::Table& table, const std::string& png, const std::string& svg,
                        std::string_view plot_template);

}  // namespace penumbra::bench
