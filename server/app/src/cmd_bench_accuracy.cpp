// `penumbra bench accuracy`: what each method's accuracy costs in time (DESIGN.md §1 "Accuracy and
// its cost in time"). Every method is rendered from the same camera as a `reference` frame (shadow
// rays marched to the light at every sample) of the same sample distance; the error is measured
// against it and set beside the frame time. The measured table doubles as the source of quality
// presets: for a frame-time budget, the most accurate setting that fits.

#include "accuracy_sweep.hpp"
#include "arguments.hpp"
#include "commands.hpp"
#include "render_options.hpp"

#include <penumbra/render/renderer.hpp>
#include <penumbra/volume/volume.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace penumbra::app {

int run_bench_accuracy(const std::vector<std::string>& args);

namespace {

using namespace accuracy;

// Defaults sized for a GPU, and lighter ones for a software rasteriser (no working timer queries,
// llvmpipe here), where the full sweep would take hours; the lighter sweep takes minutes at 256².
struct SweepDefaults {
    const char* volumes;
    const char* lights;
    const char* slices;
    const char* resolutions;
    const char* sample_distances;
    int side;
    int repeat;
};

constexpr SweepDefaults gpu_defaults{
        "/usr/share/mricron/templates/ch2.nii.gz,/usr/share/mricron/templates/ch2better.nii.gz,"
        "/usr/share/mricron/templates/inia19-t1-brain.nii.gz",
        "10,45;100,20;250,60",
        "32,64,128,256,512",
        "64,128,256,512,1024",
        "1/256,1/512",
        512,
        7};
constexpr SweepDefaults software_defaults{"/usr/share/mricron/templates/ch2.nii.gz",
                                          "10,45",
                                          "32,64,128,256",
                                          "64,128,256",
                                          "1/256",
                                          256,
                                          3};

constexpr const char* default_modes = "dvr,phong,half_angle,sbrc,sbrc_shell,sbrc_cone";

int fail(const base::Error& error) {
    return report_failure("bench accuracy", error);
}

int usage_error(const base::Error& error) {
    return report_usage_error("bench accuracy", error);
}

void print_usage() {
    std::printf(
            "usage: penumbra bench accuracy [options]\n"
            "\n"
            "Accuracy against the `reference` mode (shadow rays) versus frame time. For every\n"
            "volume and light the reference is rendered once per sample distance from the same\n"
            "camera; every other mode x slices x light-buffer resolution x sample distance is\n"
            "compared with it (RMSE and PSNR via OpenImageIO, SSIM on Rec. 601 luma) and timed:\n"
            "the median frame time over --repeat frames with the light buffer cached (only the\n"
            "camera fixed: what a user orbiting the volume pays), and, separately, the median\n"
            "light-buffer build forced by nudging the light (what a light or TF edit pays).\n"
            "Times are GPU timer queries where they work, else wall clock (software rasterisers).\n"
            "Phong shading is on in every mode that has it as an option (shadow modes and the\n"
            "reference), so the methods differ only in how they shadow; dvr is unlit.\n"
            "\n"
            "Defaults are for a GPU; on a software rasteriser (llvmpipe) lighter ones in [].\n"
            "  --volumes FILE,...             (default ch2, ch2better, inia19-t1-brain from\n"
            "                                 /usr/share/mricron/templates [ch2], and the head\n"
            "                                 CT that scripts/demo-data.sh converts, where it "
            "did)\n"
            "  --lights AZ,EL;AZ,EL...        directional lights in degrees, quote the ';'\n"
            "                                 (default 10,45;100,20;250,60 [10,45])\n"
            "  --modes LIST                   (default %s;\n"
            "                                 the reference is always rendered)\n"
            "  --slices-list N,...            (default 32,64,128,256,512 [32,64,128,256])\n"
            "  --light-res-list R,...         (default 64,128,256,512,1024 [64,128,256])\n"
            "  --sample-distances D,...       numbers or 1/N (default 1/256,1/512 [1/256])\n"
            "  --size WxH                     (default 512x512 [256x256])\n"
            "  --repeat N                     timed frames per point after 1 warm-up\n"
            "                                 (default 7 [3])\n"
            "  --no-phong                     shadow modes and reference without Blinn-Phong\n"
            "  --csv FILE  --json FILE        the measured table (one row per point)\n"
            "  --plot FILE.png                PSNR over frame time, one curve per method, Pareto\n"
            "                                 front marked; also FILE.svg and the gnuplot script\n"
            "                                 FILE.gp (needs gnuplot-nox)\n"
            "  --budget-ms MS,...             frame-time budgets for the quality presets\n"
            "                                 (default: six from the fastest setting to the\n"
            "                                 reference)\n"
            "  --from FILE.json               measure nothing: presets, CSV, JSON and plot from a\n"
            "                                 table written by --json\n"
            "  --debug-gl                     GL debug output to the log\n"
            "\n"
            "frame options (as for `penumbra render`; --mode, --slices, --light-res, --light,\n"
            "--light-position and --sample-distance are swept instead):\n%s",
            default_modes, frame_options_help());
}

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (true) {
        const std::size_t end = text.find(separator, start);
        parts.push_back(text.substr(start, end - start));
        if (end == std::string::npos) {
            return parts;
        }
        start = end + 1;
    }
}

base::Result<std::vector<int>> parse_counts(const std::string& text, const std::string& option) {
    auto numbers = parse_numbers(text, option);
    if (!numbers) {
        return numbers.error();
    }
    std::vector<int> counts;
    for (const double number : *numbers) {
        if (number < 1.0 || number > 65536.0 || std::floor(number) != number) {
            return base::make_error("invalid_argument", "expects whole numbers from 1 to 65536",
                                    "--" + option);
        }
        if (std::find(counts.begin(), counts.end(), static_cast<int>(number)) == counts.end()) {
            counts.push_back(static_cast<int>(number));
        }
    }
    return counts;
}

// "1/256,0.002" → distances (numbers accept the fraction form).
base::Result<std::vector<double>> parse_distances(const std::string& text) {
    std::vector<double> distances;
    for (const std::string& item : split(text, ',')) {
        auto number = parse_numbers(item, "sample-distances");
        if (!number) {
            return number.error();
        }
        const double value = number->front();
        if (!std::isfinite(value) || value <= 0.0 || value > 1.0) {
            return base::make_error("invalid_argument",
                                    "'" + item + "' is not a distance in (0, 1]",
                                    "--sample-distances");
        }
        distances.push_back(value);
    }
    return distances;
}

base::Result<std::vector<LightAngles>> parse_lights(const std::string& text) {
    std::vector<LightAngles> lights;
    for (const std::string& item : split(text, ';')) {
        auto numbers = parse_numbers(item, "lights");
        if (!numbers) {
            return numbers.error();
        }
        if (numbers->size() != 2) {
            return base::make_error("invalid_argument",
                                    "expects AZIMUTH,ELEVATION pairs separated by ';'", "--lights");
        }
        lights.push_back({(*numbers)[0], (*numbers)[1]});
    }
    return lights;
}

base::Result<std::vector<scene::Mode>> parse_modes(const std::string& text) {
    std::vector<scene::Mode> modes;
    for (const std::string& name : split(text, ',')) {
        const auto mode = scene::parse_mode(name);
        if (!mode) {
            return base::make_error("invalid_argument",
                                    "unknown mode '" + name +
                                            "' (dvr, phong, half_angle, sbrc, sbrc_shell, "
                                            "sbrc_cone)",
                                    "--modes");
        }
        // The reference is what the others are measured against; it is always rendered.
        if (*mode != scene::Mode::reference &&
            std::find(modes.begin(), modes.end(), *mode) == modes.end()) {
            modes.push_back(*mode);
        }
    }
    return modes;
}

// 1/256 rather than 0.00390625 wherever a person reads it.
std::string distance_label(double distance) {
    const double inverse = 1.0 / distance;
    char text[32];
    if (std::abs(inverse - std::round(inverse)) < 1e-6 * inverse) {
        std::snprintf(text, sizeof text, "1/%.0f", inverse);
    } else {
        std::snprintf(text, sizeof text, "%g", distance);
    }
    return text;
}

std::string format(const char* pattern, double value) {
    char text[256];
    std::snprintf(text, sizeof text, pattern, value);
    return text;
}

// ---------------------------------------------------------------------------------------------
// The presets.

// The settings no other setting beats in both time and accuracy, fastest first.
std::vector<Setting> pareto_front(std::vector<Setting> settings, bool worst_time) {
    const auto time = [worst_time](const Setting& s) {
        return worst_time ? s.worst_frame_ms : s.frame_ms;
    };
    std::sort(settings.begin(), settings.end(), [&](const Setting& a, const Setting& b) {
        return time(a) != time(b) ? time(a) < time(b) : more_accurate(a, b);
    });
    std::vector<Setting> front;
    for (const Setting& s : settings) {
        if (front.empty() || more_accurate(s, front.back())) {
            if (!front.empty() && s.psnr_finest == front.back().psnr_finest) {
                continue;  // as accurate and slower
            }
            front.push_back(s);
        }
    }
    return front;
}

std::string psnr_text(double psnr) {
    return std::isinf(psnr) ? "inf" : format("%.2f", psnr);
}

void print_presets(const Table& table, const std::vector<Preset>& presets) {
    std::set<std::string> volumes;
    std::set<LightAngles> lights;
    for (const Point& p : table.points) {
        volumes.insert(p.volume);
        lights.insert(p.light);
    }
    std::printf(
            "\nquality presets: per budget, the most accurate setting (mean PSNR vs reference over "
            "%zu volume(s) x %zu light(s))\nwhose slowest median frame time fits; %s time, light "
            "buffer cached (a light or TF edit adds the build)\n",
            volumes.size(), lights.size(), timing_name(table));
    std::printf("  %9s  %-11s %5s %5s %7s %8s %6s %9s %9s\n", "budget ms", "mode", "n", "R", "dt",
                "PSNR dB", "SSIM", "frame ms", "build ms");
    for (const Preset& preset : presets) {
        if (!preset.setting) {
            std::printf("  %9g  nothing measured fits\n", preset.budget_ms);
            continue;
        }
        const Setting& s = *preset.setting;
        const std::string n = s.key.slices > 0 ? std::to_string(s.key.slices) : "-";
        const std::string r = s.key.resolution > 0 ? std::to_string(s.key.resolution) : "-";
        const std::string build =
                s.light_buffer_ms > 0.0 ? format("%9.2f", s.light_buffer_ms) : "        -";
        std::printf("  %9g  %-11s %5s %5s %7s %8s %6.4f %9.2f %s\n", preset.budget_ms,
                    scene::to_string(s.key.mode), n.c_str(), r.c_str(),
                    distance_label(s.key.sample_distance).c_str(), psnr_text(s.psnr_finest).c_str(),
                    s.ssim_finest, s.worst_frame_ms, build.c_str());
    }
}

// ---------------------------------------------------------------------------------------------
// CSV and JSON.

base::Status write_csv(const Table& table, const std::string& path) {
    std::ofstream out(path);
    if (!out) {
        return base::make_error("io_error", "cannot write '" + path + "'", "--csv");
    }
    out << "volume,light_azimuth,light_elevation,mode,slices,resolution,sample_distance,width,"
           "height,timing,frame_ms,light_buffer_ms,rmse,psnr,ssim,rmse_finest,psnr_finest,"
           "ssim_finest\n";
    char line[512];
    for (const Point& p : table.points) {
        std::snprintf(line, sizeof line,
                      "%s,%g,%g,%s,%d,%d,%.9g,%d,%d,%s,%.4f,%.4f,%.6g,%s,%.6f,%.6g,%s,%.6f\n",
                      p.volume.c_str(), p.light.azimuth, p.light.elevation,
                      scene::to_string(p.mode), p.slices, p.resolution, p.sample_distance,
                      table.width, table.height, timing_name(table), p.frame_ms, p.light_buffer_ms,
                      p.rmse, psnr_text(p.psnr).c_str(), p.ssim, p.rmse_finest,
                      psnr_text(p.psnr_finest).c_str(), p.ssim_finest);
        out << line;
    }
    if (!out) {
        return base::make_error("io_error", "writing '" + path + "' failed", "--csv");
    }
    return base::Ok{};
}

// ---------------------------------------------------------------------------------------------
// The plot: a gnuplot script with its data inline, run once for PNG and once for SVG.

struct ModeStyle {
    scene::Mode mode;
    const char* colour;
    int point_type;
};

constexpr ModeStyle mode_styles[] = {
        {scene::Mode::dvr, "#7f7f7f", 5},         {scene::Mode::phong, "#000000", 7},
        {scene::Mode::half_angle, "#e07b00", 9},  {scene::Mode::sbrc, "#1f5fbf", 11},
        {scene::Mode::sbrc_shell, "#2a9d3a", 13}, {scene::Mode::sbrc_cone, "#9b30c0", 15},
};

std::string gnuplot_string(const std::string& text) {
    std::string quoted = "\"";
    for (const char c : text) {
        if (c == '\n') {
            quoted += "\\n";  // gnuplot breaks the line where a double-quoted string says \n
            continue;
        }
        if (c == '"' || c == '\\') {
            quoted += '\\';
        }
        quoted += c;
    }
    return quoted + "\"";
}

std::string data_block(const std::string& name, const std::vector<Setting>& settings) {
    std::string block = "$" + name + " << EOD\n";
    char line[128];
    for (const Setting& s : settings) {
        // Short labels keep the crowded front readable: n/R for the sliced modes.
        const std::string label = s.key.slices > 0 ? std::to_string(s.key.slices) + "/" +
                                                             std::to_string(s.key.resolution)
                                                   : std::string(scene::to_string(s.key.mode));
        std::snprintf(line, sizeof line, "%.6g %.4f \"%s\"\n", s.frame_ms, s.psnr_finest,
                      label.c_str());
        block += line;
    }
    return block + "EOD\n";
}

// One panel per volume (means over its lights): every setting of a method as a small mark, the
// method's own Pareto front as its curve, the front over all methods as a wide grey band, and the
// reference's time as a vertical line (its PSNR is infinite).
std::string gnuplot_script(const Table& table, const std::string& png, const std::string& svg) {
    std::vector<std::string> volumes;
    std::set<LightAngles> lights;
    std::set<double> distances;
    for (const Point& p : table.points) {
        if (std::find(volumes.begin(), volumes.end(), p.volume) == volumes.end()) {
            volumes.push_back(p.volume);
        }
        lights.insert(p.light);
        distances.insert(p.sample_distance);
    }
    std::string light_text;
    for (const LightAngles& l : lights) {
        light_text += (light_text.empty() ? "" : "; ") + format("%g", l.azimuth) + "," +
                      format("%g", l.elevation);
    }
    std::string distance_text;
    for (const double d : distances) {
        distance_text += (distance_text.empty() ? "" : ", ") + distance_label(d);
    }

    std::string data;
    std::string body;
    const int panels = static_cast<int>(volumes.size());
    body += "set multiplot layout 1," + std::to_string(panels) + " title " +
            gnuplot_string("Penumbra: accuracy vs frame time on " + table.device + "\n" +
                           std::to_string(table.width) + "x" + std::to_string(table.height) +
                           ", lights (az,el) " + light_text + ", sample distance " + distance_text +
                           ", tf " + table.transfer_function +
                           (table.phong ? ", Blinn-Phong on" : "")) +
            " font \",12\"\n";
    for (int v = 0; v < panels; ++v) {
        const std::string& volume = volumes[static_cast<std::size_t>(v)];
        const std::vector<Setting> settings = aggregate(table.points, volume);
        std::vector<Setting> measured;
        std::vector<Setting> references;
        for (const Setting& s : settings) {
            (s.key.mode == scene::Mode::reference ? references : measured).push_back(s);
        }
        const std::string prefix = "v" + std::to_string(v) + "_";
        data += data_block(prefix + "front", pareto_front(measured, false));
        double y_min = infinity;
        double y_max = -infinity;
        for (const Setting& s : measured) {
            y_min = std::min(y_min, s.psnr_finest);
            y_max = std::max(y_max, s.psnr_finest);
        }
        body += "set title " +
                gnuplot_string(volume + (lights.size() > 1
                                                 ? " (mean over " + std::to_string(lights.size()) +
                                                           " lights)"
                                                 : "")) +
                "\n";
        body += "unset arrow\nunset label\n";
        if (std::isfinite(y_min)) {
            body += format("set yrange [%.1f:", std::floor(y_min - 1.0)) +
                    format("%.1f]\n", std::ceil(y_max + 2.0));
        }
        for (std::size_t i = 0; i < references.size(); ++i) {
            const Setting& r = references[i];
            body += format("set arrow from %.6g, graph 0 to ", r.frame_ms) +
                    format("%.6g, graph 1 nohead dt 2 lw 1.5 lc rgb \"#c00000\"\n", r.frame_ms);
            body += "set label " +
                    gnuplot_string("reference " + distance_label(r.key.sample_distance) +
                                   " (PSNR inf)") +
                    format(" at %.6g, ", r.frame_ms) +
                    format("graph %.3f right offset -0.5,0 tc rgb \"#c00000\" font \",9\"\n",
                           0.97 - 0.05 * static_cast<double>(i));
        }
        std::string plots = "plot $" + prefix +
                            "front using 1:2 with linespoints lw 9 lc rgb \"#d0d0d0\" pt 6 ps 2.2 "
                            "title \"Pareto front (all methods)\", $" +
                            prefix +
                            "front using 1:2:3 with labels right offset -1.2,0 font \",8\" "
                            "tc rgb \"#505050\" notitle";
        for (const ModeStyle& style : mode_styles) {
            std::vector<Setting> own;
            for (const Setting& s : measured) {
                if (s.key.mode == style.mode) {
                    own.push_back(s);
                }
            }
            if (own.empty()) {
                continue;
            }
            const std::string name = prefix + scene::to_string(style.mode);
            data += data_block(name + "_all", own);
            data += data_block(name + "_front", pareto_front(own, false));
            plots += ", $" + name + "_all using 1:2 with points pt " +
                     std::to_string(style.point_type - 1) + " ps 0.6 lc rgb \"" + style.colour +
                     "\" notitle";
            plots += ", $" + name + "_front using 1:2 with linespoints lw 2 pt " +
                     std::to_string(style.point_type) + " ps 1.1 lc rgb \"" + style.colour +
                     "\" title \"" + scene::to_string(style.mode) + "\"";
        }
        body += plots + "\n";
    }
    body += "unset multiplot\n";

    const int width = 620 * panels + 80;
    std::string script =
            "# Written by `penumbra bench accuracy`; `gnuplot " +
            std::filesystem::path(png).replace_extension(".gp").string() +
            "` in this folder redraws the PNG and SVG.\n"
            "# x: median frame time with the light buffer cached (" +
            std::string(table.gpu_timers ? "GPU timer queries" : "wall clock: no GPU timers") +
            "), y: PSNR vs the reference; marks: every setting; curves: each method's Pareto "
            "front.\n";
    script += data;
    const std::string x_label =
            table.gpu_timers ? "frame time, ms (GPU timer queries, median; log scale)"
                             : "frame time, ms (wall clock, median; no GPU timer queries on this "
                               "device; log scale)";
    const std::string common =
            "set logscale x\nset grid xtics ytics mxtics lc rgb \"#e8e8e8\"\n"
            "set xlabel " +
            gnuplot_string(x_label) +
            "\nset ylabel \"PSNR vs reference, dB (higher is better); grey labels: slices n / "
            "light-buffer R\"\n"
            "set key bottom right box opaque font \",9\" spacing 1.1\nset mxtics 10\n";
    script += "set terminal pngcairo size " + std::to_string(width) +
              ",600 noenhanced font \"DejaVu Sans,10\"\nset output " + gnuplot_string(png) + "\n" +
              common + body;
    script +=
            "set terminal svg size " + std::to_string(width) +
            ",600 dynamic noenhanced font \"DejaVu Sans,10\" background \"#ffffff\"\nset output " +
            gnuplot_string(svg) + "\n" + body + "set output\n";
    return script;
}

// gnuplot writes the images; the script stays beside them so they can be redrawn or restyled.
std::string shell_quoted(const std::string& text) {
    std::string quoted = "'";
    for (const char c : text) {
        quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    }
    return quoted + "'";
}

// gnuplot writes the images; the script stays beside them, naming them without a folder, so
// `gnuplot FILE.gp` run in that folder redraws them.
base::Status write_plot(const Table& table, const std::string& png) {
    const std::filesystem::path png_path(png);
    std::filesystem::path folder = png_path.parent_path();
    if (folder.empty()) {
        folder = ".";
    }
    const std::filesystem::path svg = std::filesystem::path(png_path).replace_extension(".svg");
    const std::filesystem::path gp = std::filesystem::path(png_path).replace_extension(".gp");
    {
        std::ofstream out(gp);
        if (!out) {
            return base::make_error("io_error", "cannot write '" + gp.string() + "'", "--plot");
        }
        out << gnuplot_script(table, png_path.filename().string(), svg.filename().string());
        if (!out) {
            return base::make_error("io_error", "writing '" + gp.string() + "' failed", "--plot");
        }
    }
    const std::string command = "cd " + shell_quoted(folder.string()) + " && gnuplot " +
                                shell_quoted(gp.filename().string());
    if (std::system(command.c_str()) != 0) {
        return base::make_error("plot_failed",
                                "gnuplot failed or is missing (apt-get install gnuplot-nox); the "
                                "script is " +
                                        gp.string(),
                                "--plot");
    }
    std::printf("plot:     %s, %s (script %s)\n", png.c_str(), svg.string().c_str(),
                gp.string().c_str());
    return base::Ok{};
}

// ---------------------------------------------------------------------------------------------
// Measuring.

class Progress {
public:
    Progress(std::uint64_t total)
        : total_(total)
        , start_(Clock::now()) {}

    // "[ 12%, 1.2 of ~9.8 min]" from the frames done so far.
    std::string operator()(std::uint64_t done) const {
        const double minutes = std::chrono::duration<double>(Clock::now() - start_).count() / 60.0;
        const double fraction =
                total_ > 0 ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
        char text[64];
        std::snprintf(text, sizeof text, "[%3.0f%%, %.1f of ~%.1f min]", 100.0 * fraction, minutes,
                      fraction > 0.0 ? minutes / fraction : 0.0);
        return text;
    }

private:
    using Clock = std::chrono::steady_clock;
    std::uint64_t total_;
    Clock::time_point start_;
};

void print_view_header(const std::string& volume, const LightAngles& light) {
    std::printf("\n%s, light %g,%g\n  %-11s %5s %5s %7s %9s %9s %8s %7s\n", volume.c_str(),
                light.azimuth, light.elevation, "mode", "n", "R", "dt", "frame ms", "build ms",
                "PSNR dB", "SSIM");
}

void print_point(const Point& p, const std::string& progress) {
    const std::string n = p.slices > 0 ? std::to_string(p.slices) : "-";
    const std::string r = p.resolution > 0 ? std::to_string(p.resolution) : "-";
    const std::string build =
            p.light_buffer_ms > 0.0 ? format("%9.2f", p.light_buffer_ms) : std::string("        -");
    std::printf("  %-11s %5s %5s %7s %9.2f %s %8s %7.4f  %s\n", scene::to_string(p.mode), n.c_str(),
                r.c_str(), distance_label(p.sample_distance).c_str(), p.frame_ms, build.c_str(),
                psnr_text(p.psnr).c_str(), p.ssim, progress.c_str());
    std::fflush(stdout);
}

base::Status finish(const Table& table, const Arguments& a) {
    std::vector<double> budgets;
    if (const auto text = a.get("budget-ms")) {
        auto parsed = parse_numbers(*text, "budget-ms");
        if (!parsed) {
            return parsed.error();
        }
        budgets = *parsed;
    } else {
        budgets = default_budgets(table.points);
    }
    const std::vector<Preset> presets = choose_presets(table.points, budgets);
    print_presets(table, presets);
    if (const auto path = a.get("csv")) {
        if (auto status = write_csv(table, *path); !status) {
            return status;
        }
        std::printf("csv:      %s\n", path->c_str());
    }
    if (const auto path = a.get("json")) {
        if (auto status = write_json(table, presets, *path); !status) {
            return status;
        }
        std::printf("json:     %s\n", path->c_str());
    }
    if (const auto path = a.get("plot")) {
        if (auto status = write_plot(table, *path); !status) {
            return status;
        }
    }
    return base::Ok{};
}

}  // namespace

int run_bench_accuracy(const std::vector<std::string>& args) {
    std::vector<std::string> valued = frame_option_names();
    valued.insert(valued.end(),
                  {"volumes", "lights", "modes", "slices-list", "light-res-list",
                   "sample-distances", "repeat", "csv", "json", "plot", "budget-ms", "from"});
    std::vector<std::string> flags = frame_flag_names();
    flags.insert(flags.end(), {"help", "debug-gl", "no-phong"});
    auto parsed = Arguments::parse(args, valued, flags);
    if (!parsed) {
        return usage_error(parsed.error());
    }
    const Arguments& a = *parsed;
    if (a.has("help")) {
        print_usage();
        return 0;
    }
    // What the benchmark sweeps or fixes itself; accepting one would silently ignore it.
    const std::pair<const char*, const char*> swept[] = {
            {"mode", "--modes LIST"},
            {"slices", "--slices-list LIST"},
            {"light-res", "--light-res-list LIST"},
            {"light", "--lights LIST"},
            {"light-position", "--lights LIST (directional lights only)"},
            {"sample-distance", "--sample-distances LIST"}};
    for (const auto& [option, instead] : swept) {
        if (a.has(option)) {
            return usage_error(base::make_error(
                    "invalid_argument", std::string("bench accuracy sweeps this; use ") + instead,
                    std::string("--") + option));
        }
    }

    if (const auto from = a.get("from")) {
        auto table = read_table(*from);
        if (!table) {
            return fail(table.error());
        }
        std::printf("penumbra bench accuracy (from %s)\ngl:       %s | %s\npoints:   %zu\n",
                    from->c_str(), table->device.c_str(), table->gl_version.c_str(),
                    table->points.size());
        if (auto status = finish(*table, a); !status) {
            return fail(status.error());
        }
        return 0;
    }

    auto renderer =
            render::Renderer::create({.shader_dir = {}, .debug_context = a.has("debug-gl")});
    if (!renderer) {
        return fail(renderer.error());
    }
    const render::RendererInfo& info = (*renderer)->info();
    const SweepDefaults& defaults = info.gpu_timer_queries ? gpu_defaults : software_defaults;

    Sweep sweep;
    auto lights = parse_lights(a.get("lights").value_or(defaults.lights));
    auto modes = parse_modes(a.get("modes").value_or(default_modes));
    auto slices = parse_counts(a.get("slices-list").value_or(defaults.slices), "slices-list");
    auto resolutions =
            parse_counts(a.get("light-res-list").value_or(defaults.resolutions), "light-res-list");
    auto distances = parse_distances(a.get("sample-distances").value_or(defaults.sample_distances));
    auto repeat = a.integer("repeat", defaults.repeat);
    if (!lights || !modes || !slices || !resolutions || !distances || !repeat) {
        return usage_error(!lights        ? lights.error()
                           : !modes       ? modes.error()
                           : !slices      ? slices.error()
                           : !resolutions ? resolutions.error()
                           : !distances   ? distances.error()
                                          : repeat.error());
    }
    if (*repeat < 1 || *repeat > 1000) {
        return usage_error(base::make_error("invalid_argument", "expects 1..1000", "--repeat"));
    }
    std::string default_volumes = defaults.volumes;
    if (const auto ct = demo_ct_path()) {
        default_volumes += "," + ct->string();
    }
    sweep.volumes = split(a.get("volumes").value_or(default_volumes), ',');
    sweep.lights = *lights;
    sweep.modes = *modes;
    sweep.slices = *slices;
    sweep.resolutions = *resolutions;
    sweep.distances = *distances;
    std::sort(sweep.distances.begin(), sweep.distances.end());
    sweep.distances.erase(std::unique(sweep.distances.begin(), sweep.distances.end()),
                          sweep.distances.end());
    sweep.repeat = *repeat;

    Table table = make_table(info, sweep.repeat, !a.has("no-phong"));

    std::printf("penumbra bench accuracy\n");
    std::printf("gl:       %s | %s | %s\n", info.renderer.c_str(), info.version.c_str(),
                info.platform.c_str());
    if (info.gpu_timer_queries) {
        std::printf("timing:   GPU timer queries, median of %d frame(s) after 1 warm-up\n",
                    sweep.repeat);
    } else {
        std::printf(
                "timing:   wall clock (this GL's timer queries mean nothing: software "
                "rasteriser),\n          median of %d frame(s) after 1 warm-up; lighter "
                "defaults for a software rasteriser\n",
                sweep.repeat);
    }

    AccuracyBench bench(**renderer, sweep.repeat);
    const std::uint64_t frames_per_volume = frames_per_view(sweep) * sweep.lights.size();
    const Progress progress(frames_per_volume * sweep.volumes.size());
    std::printf(
            "sweep:    %zu volume(s) x %zu light(s): %llu frames (progress shows the time "
            "left)\n",
            sweep.volumes.size(), sweep.lights.size(),
            static_cast<unsigned long long>(frames_per_volume * sweep.volumes.size()));
    for (std::size_t v = 0; v < sweep.volumes.size(); ++v) {
        const std::string& path = sweep.volumes[v];
        auto loaded = volume::load_volume(path);
        if (!loaded) {
            return fail(loaded.error());
        }
        auto volume = std::make_shared<const volume::Volume>(std::move(loaded.value()));
        auto base_request = frame_request_from(a, *volume);
        if (!base_request) {
            return fail(base_request.error());
        }
        scene::FrameRequest& base = *base_request;
        if (!a.has("size")) {
            base.settings.width = defaults.side;
            base.settings.height = defaults.side;
        }
        if (base.settings.width < min_image_side || base.settings.height < min_image_side) {
            return usage_error(base::make_error("invalid_argument",
                                                "SSIM needs images of at least " +
                                                        std::to_string(min_image_side) + "x" +
                                                        std::to_string(min_image_side),
                                                "--size"));
        }
        base.settings.phong = table.phong;
        if (v == 0) {
            describe_frame(table, base);
            std::printf(
                    "frame:    %dx%d, tf %s, %s compositing, %s stage, builder %s, light lookup "
                    "%s, slab samples %d, phong %s\n",
                    table.width, table.height, table.transfer_function.c_str(),
                    table.compositing.c_str(), table.stage.c_str(), table.builder.c_str(),
                    table.light_lookup.c_str(), table.slab_samples, table.phong ? "on" : "off");
            std::fflush(stdout);
        }
        if (auto status = (*renderer)->set_volume(volume); !status) {
            return fail(status.error());
        }
        const PointObserver print = [&](const Point& p) {
            print_point(p, progress(bench.frames()));
            return true;
        };
        for (const LightAngles& light : sweep.lights) {
            print_view_header(volume->name, light);
            if (auto measured =
                        measure_view(bench, sweep, base, volume->name, light, print, table.points);
                !measured) {
                return fail(measured.error());
            }
        }
    }
    if (auto status = finish(table, a); !status) {
        return fail(status.error());
    }
    return 0;
}

}  // namespace penumbra::app
