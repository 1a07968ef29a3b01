#include "penumbra/bench/report.hpp"

#include <penumbra/base/data_dir.hpp>
#include <penumbra/bench/plot_style.hpp>
#include <penumbra/bench/truth.hpp>
#include <penumbra/scene/mode.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

namespace penumbra::bench {
namespace {

std::string format(const char* pattern, double value) {
    char text[256];
    std::snprintf(text, sizeof text, pattern, value);
    return text;
}

// A gnuplot string literal; gnuplot breaks the line where a double-quoted string says \n.
std::string gnuplot_string(const std::string& text) {
    std::string quoted = "\"";
    for (const char c : text) {
        if (c == '\n') {
            quoted += "\\n";
            continue;
        }
        if (c == '"' || c == '\\') {
            quoted += '\\';
        }
        quoted += c;
    }
    return quoted + "\"";
}

// "array name[3] = [a, b, c]"; nothing for no values (gnuplot has no empty arrays).
std::string gnuplot_array(const std::string& name, const std::vector<std::string>& values) {
    if (values.empty()) {
        return {};
    }
    std::string out = "array " + name + "[" + std::to_string(values.size()) + "] = [";
    for (std::size_t i = 0; i < values.size(); ++i) {
        out += (i == 0 ? "" : ", ") + values[i];
    }
    return out + "]\n";
}

// Short labels keep the crowded front readable: n/R for the sliced modes.
std::string setting_label(const quality::Setting& s) {
    return s.key.slices > 0 ? std::to_string(s.key.slices) + "/" + std::to_string(s.key.resolution)
                            : std::string(scene::to_string(s.key.mode));
}

struct PlotText {
    std::string variables;
    std::string front = "$front << EOD\n";
    std::string all = "$all << EOD\n";
    std::string own = "$own << EOD\n";
    std::string variants = "$variants << EOD\n";
    std::set<int> variant_kinds;
};

// How a setting differs from the request's defaults, as the plot marks it (the template's
// variant_point and variant_title): 0 plain, else the most telling difference.
int variant_kind(const quality::SettingKey& key) {
    if (key.refinement_steps > 0) {
        return 3;
    }
    if (key.jitter) {
        return 2;
    }
    return key.empty_space_skipping ? 0 : 1;
}

// "" (the defaults), "no-skip" (no empty-space skipping), "jit" (jittered), "jit+8" (refined by
// 8 steps), "no-skip,jit".
std::string variant_text(const quality::SettingKey& key) {
    std::string text = key.empty_space_skipping ? "" : "no-skip";
    if (key.jitter) {
        text += (text.empty() ? "" : ",") + std::string("jit");
        if (key.refinement_steps > 0) {
            text += "+" + std::to_string(key.refinement_steps);
        }
    }
    return text;
}

// The time until the setting's image is on screen: a refined image after its still and steps.
double time_to_image(const quality::Setting& s) {
    return s.frame_ms * (1.0 + s.key.refinement_steps);
}

// What the table's *_truth columns compare with.
std::string truth_text(const quality::Table& table) {
    return table.truth ? describe(*table.truth) : "the reference at the finest sample distance";
}

// The figure's title: device; size, lights, sample distances, TF; the truth.
std::string title_of(const quality::Table& table) {
    std::set<quality::LightAngles> lights;
    std::set<double> distances;
    for (const quality::Point& p : table.points) {
        lights.insert(p.light);
        distances.insert(p.sample_distance);
    }
    std::string light_text;
    for (const quality::LightAngles& l : lights) {
        light_text += (light_text.empty() ? "" : "; ") + format("%g", l.azimuth) + "," +
                      format("%g", l.elevation);
    }
    std::string distance_text;
    for (const double d : distances) {
        distance_text += (distance_text.empty() ? "" : ", ") + distance_label(d);
    }
    return "Penumbra: accuracy vs frame time on " + table.device + "\n" +
           std::to_string(table.width) + "x" + std::to_string(table.height) + ", lights (az,el) " +
           light_text + ", sample distance " + distance_text + ", tf " + table.transfer_function +
           (table.phong ? ", Blinn-Phong on" : "") +
           "\nPSNR against the truth: " + truth_text(table);
}

// One panel's data rows, its title, y range and references.
void add_panel(const quality::Table& table, const std::string& volume, int panel,
               std::size_t lights, const std::vector<scene::Mode>& modes, PlotText& text,
               std::vector<std::string> (&references)[4], std::vector<std::string>& titles,
               std::vector<std::string>& ranges) {
    std::vector<quality::Setting> measured;
    int row = 0;
    for (const quality::Setting& s : quality::aggregate(table.points, volume)) {
        if (!std::isinf(s.psnr_truth)) {
            measured.push_back(s);
            continue;
        }
        // The truth itself (a table without a converged truth): a line at its time.
        references[0].push_back(std::to_string(panel));
        references[1].push_back(format("%.6g", s.frame_ms));
        references[2].push_back(gnuplot_string(
                "reference " + distance_label(s.key.sample_distance) +
                (s.key.empty_space_skipping ? "" : " no skipping") + " (the truth)"));
        references[3].push_back(std::to_string(row++));
    }
    const std::string p = std::to_string(panel) + " ";
    std::vector<quality::Setting> plain;
    for (const quality::Setting& s : measured) {
        if (s.key.plain()) {
            plain.push_back(s);
            continue;
        }
        const auto mode = std::find(modes.begin(), modes.end(), s.key.mode) - modes.begin() + 1;
        const int kind = variant_kind(s.key);
        text.variant_kinds.insert(kind);
        text.variants += p + std::to_string(mode) + " " + format("%.6g ", time_to_image(s)) +
                         format("%.4f ", s.psnr_truth) + std::to_string(kind) + "\n";
    }
    measured = plain;
    for (const quality::Setting& s : pareto_front(measured, false)) {
        text.front += p + format("%.6g ", s.frame_ms) + format("%.4f ", s.psnr_truth) +
                      gnuplot_string(setting_label(s)) + "\n";
    }
    double y_min = quality::infinity;
    double y_max = -quality::infinity;
    for (const quality::Setting& s : quality::aggregate(table.points, volume)) {
        if (!std::isinf(s.psnr_truth) && !s.key.plain()) {
            y_min = std::min(y_min, s.psnr_truth);
            y_max = std::max(y_max, s.psnr_truth);
        }
    }
    for (std::size_t m = 0; m < modes.size(); ++m) {
        std::vector<quality::Setting> own;
        for (const quality::Setting& s : measured) {
            if (s.key.mode == modes[m]) {
                own.push_back(s);
                y_min = std::min(y_min, s.psnr_truth);
                y_max = std::max(y_max, s.psnr_truth);
            }
        }
        const std::string pm = p + std::to_string(m + 1) + " ";
        for (const quality::Setting& s : own) {
            text.all += pm + format("%.6g ", s.frame_ms) + format("%.4f\n", s.psnr_truth);
        }
        for (const quality::Setting& s : pareto_front(own, false)) {
            text.own += pm + format("%.6g ", s.frame_ms) + format("%.4f\n", s.psnr_truth);
        }
    }
    titles.push_back(gnuplot_string(
            volume + (lights > 1 ? " (mean over " + std::to_string(lights) + " lights)" : "")));
    ranges.push_back(std::isfinite(y_min) ? "\"[" + format("%.1f:", std::floor(y_min - 1.0)) +
                                                    format("%.1f]\"", std::ceil(y_max + 2.0))
                                          : "\"[*:*]\"");
}

}  // namespace

std::string psnr_text(double psnr) {
    return std::isinf(psnr) ? "inf" : format("%.2f", psnr);
}

std::string distance_label(double distance) {
    const double inverse = 1.0 / distance;
    if (std::abs(inverse - std::round(inverse)) < 1e-6 * inverse) {
        return format("1/%.0f", inverse);
    }
    return format("%g", distance);
}

std::vector<quality::Setting> pareto_front(std::vector<quality::Setting> settings,
                                           bool worst_time) {
    const auto time = [worst_time](const quality::Setting& s) {
        return worst_time ? s.worst_frame_ms : s.frame_ms;
    };
    std::sort(settings.begin(), settings.end(),
              [&](const quality::Setting& a, const quality::Setting& b) {
                  return time(a) != time(b) ? time(a) < time(b) : quality::more_accurate(a, b);
              });
    std::vector<quality::Setting> front;
    for (const quality::Setting& s : settings) {
        if (front.empty() || quality::more_accurate(s, front.back())) {
            if (!front.empty() && s.psnr_truth == front.back().psnr_truth) {
                continue;  // as accurate and slower
            }
            front.push_back(s);
        }
    }
    return front;
}

base::Status write_csv(const quality::Table& table, const std::filesystem::path& path,
                       const std::string& where) {
    std::ofstream out(path);
    if (!out) {
        return base::make_error(base::ErrorCode::io_error, "cannot write '" + path.string() + "'",
                                where);
    }
    out << "volume,light_azimuth,light_elevation,mode,slices,resolution,sample_distance,"
           "empty_space_skipping,jitter,refinement_steps,width,height,timing,frame_ms,"
           "light_buffer_ms,rmse_truth,psnr_truth,ssim_truth,rmse,psnr,ssim\n";
    char line[512];
    for (const quality::Point& p : table.points) {
        std::snprintf(line, sizeof line,
                      "%s,%g,%g,%s,%d,%d,%.9g,%d,%d,%d,%d,%d,%s,%.4f,%.4f,%.6g,%s,%.6f,%.6g,%s,"
                      "%.6f\n",
                      p.volume.c_str(), p.light.azimuth, p.light.elevation,
                      scene::to_string(p.mode), p.slices, p.resolution, p.sample_distance,
                      p.empty_space_skipping ? 1 : 0, p.jitter ? 1 : 0, p.refinement_steps,
                      table.width, table.height, quality::timing_name(table), p.frame_ms,
                      p.light_buffer_ms, p.rmse_truth, psnr_text(p.psnr_truth).c_str(),
                      p.ssim_truth, p.rmse, psnr_text(p.psnr).c_str(), p.ssim);
        out << line;
    }
    if (!out) {
        return base::make_error(base::ErrorCode::io_error, "writing '" + path.string() + "' failed",
                                where);
    }
    return base::Ok{};
}

std::string presets_text(const quality::Table& table, const std::vector<quality::Preset>& presets) {
    std::set<std::string> volumes;
    std::set<quality::LightAngles> lights;
    for (const quality::Point& p : table.points) {
        volumes.insert(p.volume);
        lights.insert(p.light);
    }
    char line[512];
    std::snprintf(line, sizeof line,
                  "\nquality presets: per budget, the most accurate setting (mean PSNR vs the "
                  "truth over %zu volume(s) x %zu light(s))\nwhose slowest median frame time "
                  "fits; %s time, light buffer cached (a light or TF edit adds the build); the "
                  "truth: %s\n",
                  volumes.size(), lights.size(), quality::timing_name(table),
                  truth_text(table).c_str());
    std::string text = line;
    std::snprintf(line, sizeof line, "  %9s  %-11s %5s %5s %7s %-13s %8s %6s %9s %9s\n",
                  "budget ms", "mode", "n", "R", "dt", "variant", "PSNR dB", "SSIM", "frame ms",
                  "build ms");
    text += line;
    for (const quality::Preset& preset : presets) {
        if (!preset.setting) {
            std::snprintf(line, sizeof line, "  %9g  nothing measured fits\n", preset.budget_ms);
            text += line;
            continue;
        }
        const quality::Setting& s = *preset.setting;
        const std::string n = s.key.slices > 0 ? std::to_string(s.key.slices) : "-";
        const std::string r = s.key.resolution > 0 ? std::to_string(s.key.resolution) : "-";
        const std::string build =
                s.light_buffer_ms > 0.0 ? format("%9.2f", s.light_buffer_ms) : "        -";
        std::snprintf(line, sizeof line, "  %9g  %-11s %5s %5s %7s %-13s %8s %6.4f %9.2f %s\n",
                      preset.budget_ms, scene::to_string(s.key.mode), n.c_str(), r.c_str(),
                      distance_label(s.key.sample_distance).c_str(), variant_text(s.key).c_str(),
                      psnr_text(s.psnr_truth).c_str(), s.ssim_truth, s.worst_frame_ms,
                      build.c_str());
        text += line;
    }
    return text;
}

std::string frame_text(const quality::Table& table) {
    char line[512];
    std::snprintf(line, sizeof line,
                  "frame:    %dx%d, tf %s, %s compositing, %s stage, builder %s, light lookup "
                  "%s, slab samples %d, phong %s\n",
                  table.width, table.height, table.transfer_function.c_str(),
                  table.compositing.c_str(), table.stage.c_str(), table.builder.c_str(),
                  table.light_lookup.c_str(), table.slab_samples, table.phong ? "on" : "off");
    return line;
}

std::string view_header(const std::string& volume, const quality::LightAngles& light) {
    char line[512];
    std::snprintf(line, sizeof line,
                  "\n%s, light %g,%g\n  %-11s %5s %5s %7s %-13s %9s %9s %17s %17s\n  %-11s %5s "
                  "%5s %7s %-13s %9s %9s %8s %8s %8s %8s\n",
                  volume.c_str(), light.azimuth, light.elevation, "", "", "", "", "", "", "",
                  "vs the truth", "vs same-dt ref.", "mode", "n", "R", "dt", "variant", "frame ms",
                  "build ms", "PSNR dB", "SSIM", "PSNR dB", "SSIM");
    return line;
}

std::string point_row(const quality::Point& p) {
    const std::string n = p.slices > 0 ? std::to_string(p.slices) : "-";
    const std::string r = p.resolution > 0 ? std::to_string(p.resolution) : "-";
    const std::string build =
            p.light_buffer_ms > 0.0 ? format("%9.2f", p.light_buffer_ms) : "        -";
    const quality::SettingKey key{
            p.mode,   p.slices,          p.resolution, p.sample_distance, p.empty_space_skipping,
            p.jitter, p.refinement_steps};
    char line[512];
    std::snprintf(line, sizeof line, "  %-11s %5s %5s %7s %-13s %9.2f %s %8s %8.4f %8s %8.4f",
                  scene::to_string(p.mode), n.c_str(), r.c_str(),
                  distance_label(p.sample_distance).c_str(), variant_text(key).c_str(), p.frame_ms,
                  build.c_str(), psnr_text(p.psnr_truth).c_str(), p.ssim_truth,
                  psnr_text(p.psnr).c_str(), p.ssim);
    return line;
}

namespace {

// For the shell that runs gnuplot.
std::string shell_quoted(const std::string& text) {
    std::string quoted = "'";
    for (const char c : text) {
        quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    }
    return quoted + "'";
}

}  // namespace

base::Result<PlotFiles> write_plot(const quality::Table& table, const std::filesystem::path& png,
                                   const std::string& where) {
    std::filesystem::path folder = png.parent_path();
    if (folder.empty()) {
        folder = ".";
    }
    const PlotFiles files{png, std::filesystem::path(png).replace_extension(".svg"),
                          std::filesystem::path(png).replace_extension(".gp")};
    auto plot_template = read_plot_template();
    if (!plot_template) {
        return plot_template.error();
    }
    {
        std::ofstream out(files.script);
        if (!out) {
            return base::make_error(base::ErrorCode::io_error,
                                    "cannot write '" + files.script.string() + "'", where);
        }
        out << plot_script(table, png.filename().string(), files.svg.filename().string(),
                           *plot_template);
        if (!out) {
            return base::make_error(base::ErrorCode::io_error,
                                    "writing '" + files.script.string() + "' failed", where);
        }
    }
    const std::string command = "cd " + shell_quoted(folder.string()) + " && gnuplot " +
                                shell_quoted(files.script.filename().string());
    if (std::system(command.c_str()) != 0) {
        return base::make_error(base::ErrorCode::plot_failed,
                                "gnuplot failed or is missing (apt-get install gnuplot-nox); the "
                                "script is " +
                                        files.script.string(),
                                where);
    }
    return files;
}

base::Result<std::string> read_plot_template() {
    const std::filesystem::path path =
            base::data_dir("plots").value_or("share/penumbra/plots") / "accuracy.gp";
    std::ifstream in(path);
    if (!in) {
        return base::make_error(base::ErrorCode::not_found,
                                "cannot read the plot template '" + path.string() + "'", "--plot");
    }
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

std::string plot_script(const quality::Table& table, const std::string& png, const std::string& svg,
                        std::string_view plot_template) {
    std::vector<std::string> volumes;
    std::set<quality::LightAngles> lights;
    std::vector<scene::Mode> modes;
    for (const quality::Point& p : table.points) {
        if (std::find(volumes.begin(), volumes.end(), p.volume) == volumes.end()) {
            volumes.push_back(p.volume);
        }
        lights.insert(p.light);
        // Every mode measured against a truth other than itself (the reference too, where the
        // truth is the converged one).
        if (!std::isinf(p.psnr_truth) &&
            std::find(modes.begin(), modes.end(), p.mode) == modes.end()) {
            modes.push_back(p.mode);
        }
    }
    std::sort(modes.begin(), modes.end());
    PlotText text;
    std::vector<std::string> references[4];  // panel, ms, text, row
    std::vector<std::string> titles;
    std::vector<std::string> ranges;
    for (std::size_t v = 0; v < volumes.size(); ++v) {
        add_panel(table, volumes[v], static_cast<int>(v) + 1, lights.size(), modes, text,
                  references, titles, ranges);
    }
    std::string kinds;
    for (const int kind : text.variant_kinds) {
        kinds += (kinds.empty() ? "" : " ") + std::to_string(kind);
    }
    std::string mode_words;
    for (const scene::Mode mode : modes) {
        mode_words += (mode_words.empty() ? "" : " ") + std::string(scene::to_string(mode));
    }
    // Each mode's colour and point type.
    std::string style_modes;
    std::string style_colours;
    std::string style_points;
    for (const PlotStyle& style : kPlotStyles) {
        const char* gap = style_modes.empty() ? "" : " ";
        style_modes += gap + std::string(scene::to_string(style.mode));
        style_colours += gap + std::string(style.colour);
        style_points += gap + std::to_string(style.point_type);
    }
    const std::string x_label =
            table.gpu_timers ? "frame time, ms (GPU timer queries, median; log scale)"
                             : "frame time, ms (wall clock, median; no GPU timer queries on this "
                               "device; log scale)";
    const std::string y_label =
            "PSNR vs " + std::string(table.truth ? "the converged truth" : "the finest reference") +
            ", dB (higher is better); grey labels: n / R";
    std::string script =
            "# Written by `penumbra bench accuracy`; `gnuplot " +
            std::filesystem::path(png).replace_extension(".gp").string() +
            "` in this folder redraws the PNG and SVG.\n"
            "# x: median frame time with the light buffer cached, y: PSNR vs the truth; "
            "marks: every setting; curves: each method's Pareto front; open marks: no "
            "skipping, jittered, refined (at the time its steps take in all).\n";
    script += "png = " + gnuplot_string(png) + "\nsvg = " + gnuplot_string(svg) + "\n";
    // One panel still gets room for the two lines of the figure's title.
    script += "width = " + std::to_string(std::max<std::size_t>(960, 620 * volumes.size() + 80)) +
              "\ntitle_text = " + gnuplot_string(title_of(table)) +
              "\nx_label = " + gnuplot_string(x_label) + "\ny_label = " + gnuplot_string(y_label) +
              "\npanels = " + std::to_string(volumes.size()) +
              "\nmodes = " + gnuplot_string(mode_words) +
              "\nstyle_modes = " + gnuplot_string(style_modes) +
              "\nstyle_colours = " + gnuplot_string(style_colours) +
              "\nstyle_points = " + gnuplot_string(style_points) +
              "\nref_count = " + std::to_string(references[0].size()) +
              "\nvariant_kinds = " + gnuplot_string(kinds) + "\n";
    script += gnuplot_array("panel_title", titles) + gnuplot_array("y_range", ranges) +
              gnuplot_array("ref_panel", references[0]) + gnuplot_array("ref_ms", references[1]) +
              gnuplot_array("ref_text", references[2]) + gnuplot_array("ref_row", references[3]);
    script += text.front + "EOD\n" + text.all + "EOD\n" + text.own + "EOD\n" + text.variants +
              "EOD\n\n";
    return script + std::string(plot_template);
}

}  // namespace penumbra::bench
