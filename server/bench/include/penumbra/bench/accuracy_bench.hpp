#pragma once

// `penumbra bench accuracy` as a whole: the sweep measured and printed as it goes (sweep.hpp),
// then the quality presets for frame-time budgets and the table's files (report.hpp,
// quality/table_json.hpp).

#include <penumbra/base/result.hpp>
#include <penumbra/bench/truth.hpp>
#include <penumbra/quality/sweep.hpp>
#include <penumbra/quality/table.hpp>
#include <penumbra/render/renderer.hpp>

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::bench {

// How a table is reported: the presets for these budgets (empty: default_budgets), and the files
// asked for; errors name the options --csv, --json and --plot.
struct AccuracyReport {
    std::vector<double> budgets_ms;
    std::optional<std::string> csv;
    std::optional<std::string> json;
    std::optional<std::string> plot;
};

// The renderer and how it times, then every volume of `sweep` under every light measured into
// `table` (made by make_table for this renderer) against the converged truth kept in `truths`,
// each point printed as it is measured.
base::Status bench_accuracy(render::Renderer& renderer, const quality::Sweep& sweep,
                            const quality::FrameFor& frame_for, TruthCache& truths,
                            quality::Table& table, std::FILE* out);

// The presets for the budgets, printed, and the files written.
base::Status report_accuracy(const quality::Table& table, const AccuracyReport& report,
                             std::FILE* out);

// The same from a table measured before (written by --json), measuring nothing: the file, the
// renderer it was measured on and its size printed first.
base::Status report_accuracy_file(const std::string& path, const AccuracyReport& report,
                                  std::FILE* out);

}  // namespace penumbra::bench
