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

namespace penumbra::quality {

// "inf" or "23.45".
std::string psnr_text(double psnr);

// 1/256 rather than 0.00390625 wherever a person reads it.
std::string distance_label(double distance);

// The settings no other setting beats in both time and accuracy, fastest first; by the slowest
// frame where `worst_time`, else by the mean.
std::vector<Setting> pareto_front(std::vector<Setting> settings, bool worst_time);

// One row per point; errors name `where`.
base::Status write_csv(const Table& table, const std::filesystem::path& path,
                       const std::string& where);

// The plot template, from share/penumbra/plots.
base::Result<std::string> read_plot_template();

// A gnuplot script that draws `png` and `svg` (names in the folder it runs in): the table's data
// and the template's variables, then `plot_template`.
std::string plot_script(const Table& table, const std::string& png, const std::string& svg,
                        std::string_view plot_template);

}  // namespace penumbra::quality
