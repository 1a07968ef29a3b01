#include "arguments.hpp"
#include "commands.hpp"
#include "render_options.hpp"

#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/camera.hpp>
#include <penumbra/volume/volume.hpp>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::app {
namespace {

// Every frame of a series sees a new view, as a user dragging the camera would, while the work
// per frame stays comparable from one frame to the next.
constexpr double orbit_step_degrees = 2.0;
// Small enough to leave the image unchanged, large enough to change the light buffer's key.
constexpr double light_nudge_degrees = 0.01;
constexpr double point_light_nudge = 1e-4;  // world units; the volume's longest side is 1

constexpr scene::LightBufferBuilder builders[] = {scene::LightBufferBuilder::per_slice,
                                                  scene::LightBufferBuilder::multi_slice};

int fail(const base::Error& error) {
    return report_failure("bench", error);
}

int usage_error(const base::Error& error) {
    return report_usage_error("bench", error);
}

void print_bench_usage() {
    std::puts(
            "usage: penumbra bench <benchmark> [options]\n"
            "\n"
            "benchmarks:\n"
            "  modes    frame time of every rendering mode over slices x light-buffer resolution,\n"
            "           light-buffer reuse vs rebuild, and the two light-buffer builders\n"
            "  accuracy error vs the reference (RMSE, PSNR, SSIM) against frame time over\n"
            "           modes x slices x light-buffer resolution x sample distance; quality\n"
            "           presets per frame-time budget; CSV, JSON and a plot\n"
            "\n"
            "`penumbra bench <benchmark> --help` lists its options.");
}

void print_modes_usage() {
    std::printf(
            "usage: penumbra bench modes [options]\n"
            "\n"
            "Times each mode side by side in one run and prints the ratios that matter:\n"
            "half_angle vs sbrc at equal slices, sbrc's growth with slices, per_slice vs\n"
            "multi_slice builder, the local light lookup vs the paper's. Absolute times mean "
            "something only on a GPU; on a software\n"
            "rasteriser read the ratios.\n"
            "\n"
            "  --volume FILE                  (default %s)\n"
            "  --modes LIST                   modes to time, comma-separated (default: every\n"
            "                                 mode); the builder comparison runs when a sbrc\n"
            "                                 mode is listed\n"
            "  --slices-list N,...            light slices n to sweep (default 64,128,256)\n"
            "  --light-res-list R,...         light-buffer resolutions R to sweep (default\n"
            "                                 128,256,512)\n"
            "  --repeat N                     timed frames per point after 1 warm-up (default 5)\n"
            "  --csv FILE                     also write one row per measured point\n"
            "  --debug-gl                     GL debug output to the log\n"
            "\n"
            "frame options (as for `penumbra render`; --mode, --slices and --light-res are swept\n"
            "instead; --builder and --light-lookup pick what the sbrc modes use; the paper's\n"
            "method is --light-lookup interpolate --slab-samples 1):\n%s",
            default_volume_path, frame_options_help());
}

double median(std::vector<double> values) {
    if (values.empty()) {
        return 0.0;
    }
    std::sort(values.begin(), values.end());
    const std::size_t middle = values.size() / 2;
    return values.size() % 2 == 1 ? values[middle] : 0.5 * (values[middle - 1] + values[middle]);
}

// "64,128,256" → counts, each a whole number of at least 1.
base::Result<std::vector<int>> parse_counts(const Arguments& args, const std::string& option,
                                            const std::string& fallback) {
    auto numbers = parse_numbers(args.get(option).value_or(fallback), option);
    if (!numbers) {
        return numbers.error();
    }
    std::vector<int> counts;
    for (const double number : *numbers) {
        if (number < 1.0 || number > 65536.0 || std::floor(number) != number) {
            return base::make_error("invalid_argument", "expects whole numbers from 1 to 65536",
                                    "--" + option);
        }
        counts.push_back(static_cast<int>(number));
    }
    return counts;
}

base::Result<std::vector<scene::Mode>> parse_modes(const std::string& text) {
    std::vector<scene::Mode> modes;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = text.find(',', start);
        const std::string name = text.substr(start, comma - start);
        const auto mode = scene::parse_mode(name);
        if (!mode) {
            return base::make_error("invalid_argument",
                                    "unknown mode '" + name + "' (" + scene::mode_names() + ")",
                                    "--modes");
        }
        if (std::find(modes.begin(), modes.end(), *mode) == modes.end()) {
            modes.push_back(*mode);
        }
        if (comma == std::string::npos) {
            return modes;
        }
        start = comma + 1;
    }
}

// The median cost of one frame (or of one pass) over a series.
struct Measurement {
    double wall_ms = 0.0;
    std::optional<double> gpu_ms;  // absent where the GL's timer queries mean nothing
};

// What a series does to the light buffer between its timed frames, and so what each of those
// frames must report for the series to measure what its name says.
enum class LightBufferUse { none, cached, rebuild };

struct Point {
    scene::Mode mode = scene::Mode::dvr;
    std::string series;   // "frame", "cached", "rebuild" or "light_buffer_pass"
    std::string builder;  // empty where no light buffer is built
    int slices = 0;       // 0 where the mode does not depend on it
    int resolution = 0;
    Measurement measurement;
};

// The azimuth, elevation and distance that reproduce a camera with scene::orbit_camera.
struct Orbit {
    double azimuth = 0.0;
    double elevation = 0.0;
    double distance = 1.0;
    glm::dvec3 target{0.0};
    double fov_y_degrees = 30.0;
};

Orbit orbit_of(const scene::Camera& camera) {
    const glm::dvec3 offset = camera.eye - camera.target;
    const double distance = glm::length(offset);
    return {glm::degrees(std::atan2(offset.x, offset.y)),
            glm::degrees(std::asin(std::clamp(offset.z / distance, -1.0, 1.0))), distance,
            camera.target, camera.fov_y_degrees};
}

glm::dvec3 rotated(const glm::dvec3& v, const glm::dvec3& axis, double degrees) {
    const double angle = glm::radians(degrees);
    return v * std::cos(angle) + glm::cross(axis, v) * std::sin(angle) +
           axis * glm::dot(axis, v) * (1.0 - std::cos(angle));
}

// The light moved by a hair: a change of azimuth, or of elevation for a light straight above,
// whose azimuth is undefined; a point light moves sideways instead.
scene::Light nudged(scene::Light light, double sign) {
    if (light.type == scene::LightType::point) {
        light.position.x += sign * point_light_nudge;
        return light;
    }
    const glm::dvec3 axis = std::abs(light.direction.z) > 0.999 ? glm::dvec3(1.0, 0.0, 0.0)
                                                                : glm::dvec3(0.0, 0.0, 1.0);
    light.direction = rotated(light.direction, axis, sign * light_nudge_degrees);
    return light;
}

std::string point_label(const Point& point) {
    std::string label = scene::to_string(point.mode);
    if (point.slices > 0) {
        label += " n=" + std::to_string(point.slices) + " R=" + std::to_string(point.resolution);
    }
    if (!point.builder.empty() && point.series == "light_buffer_pass") {
        label += " builder " + point.builder;
    }
    return label;
}

class ModeBench {
public:
    ModeBench(render::Renderer& renderer, scene::FrameRequest base, int repeat)
        : renderer_(renderer)
        , base_(std::move(base))
        , orbit_(orbit_of(base_.camera))
        , repeat_(repeat)
        , gpu_timers_(renderer.info().gpu_timer_queries) {}

    [[nodiscard]] const scene::FrameRequest& base() const { return base_; }

    [[nodiscard]] bool gpu_timers() const { return gpu_timers_; }

    // A request for one point of the sweep, from the defaults every point shares.
    [[nodiscard]] scene::FrameRequest request(scene::Mode mode, int slices, int resolution) const {
        scene::FrameRequest r = base_;
        r.settings.mode = mode;
        if (slices > 0) {
            r.settings.light_buffer.slices = slices;
            r.settings.light_buffer.resolution = resolution;
        }
        return r;
    }

    // Renders one warm-up frame, which builds caches and compiles the shader variant, then
    // `repeat` timed frames; `pass` empty times the whole frame, otherwise that pass alone.
    base::Result<Measurement> measure(const Point& point, scene::FrameRequest request,
                                      LightBufferUse use, const std::string& pass = {}) {
        std::vector<double> wall;
        std::vector<double> gpu;
        for (int i = 0; i <= repeat_; ++i) {
            request.camera = scene::orbit_camera(orbit_.azimuth + orbit_step_degrees * i,
                                                 orbit_.elevation, orbit_.distance, orbit_.target);
            request.camera.fov_y_degrees = orbit_.fov_y_degrees;
            if (use == LightBufferUse::rebuild) {
                // A light never used before: the renderer caches light buffers by their inputs,
                // so returning to an earlier light would reuse its buffer.
                ++nudges_;
                request.light = nudged(base_.light, (nudges_ % 2 == 0 ? 1.0 : -1.0) *
                                                            static_cast<double>(nudges_ % 4096));
            }
            auto frame = renderer_.render(request);
            if (!frame) {
                return frame.error();
            }
            if (i == 0) {
                continue;
            }
            const std::string& light_buffer = frame->report.light_buffer;
            if (use == LightBufferUse::cached && light_buffer != "reused") {
                return base::make_error(
                        "bench_invalid",
                        point_label(point) + ": the light buffer was '" + light_buffer +
                                "' in a frame where only the camera moved, so 'cached' would "
                                "not measure reuse",
                        "light_buffer");
            }
            if (use == LightBufferUse::rebuild && light_buffer != "built") {
                return base::make_error(
                        "bench_invalid",
                        point_label(point) + ": the light buffer was '" + light_buffer +
                                "' in a frame whose light moved, so 'rebuild' would not "
                                "measure a rebuild",
                        "light_buffer");
            }
            double wall_ms = 0.0;
            double gpu_ms = 0.0;
            bool found = pass.empty();
            for (const auto& timing : frame->report.passes) {
                if (pass.empty() || timing.name == pass) {
                    found = true;
                    wall_ms += timing.wall_ms;
                    gpu_ms += std::max(timing.gpu_ms, 0.0);
                }
            }
            if (!found) {
                return base::make_error("bench_invalid",
                                        point_label(point) + ": no pass '" + pass +
                                                "' in a frame that rebuilt the light buffer",
                                        "light_buffer");
            }
            wall.push_back(wall_ms);
            gpu.push_back(gpu_ms);
        }
        Measurement measurement{median(wall), std::nullopt};
        if (gpu_timers_) {
            measurement.gpu_ms = median(gpu);
        }
        return measurement;
    }

private:
    render::Renderer& renderer_;
    scene::FrameRequest base_;
    Orbit orbit_;
    int repeat_;
    std::uint64_t nudges_ = 0;  // distinct lights the rebuild frames have used so far
    bool gpu_timers_;
};

// The sweep's results, looked up again for the ratios and written to the CSV as they come.
class Results {
public:
    explicit Results(std::ofstream* csv, int width, int height, int frames)
        : csv_(csv)
        , width_(width)
        , height_(height)
        , frames_(frames) {
        if (csv_ != nullptr) {
            *csv_ << "mode,series,builder,slices,light_res,width,height,frames,wall_ms,gpu_ms\n";
        }
    }

    void add(const Point& point) {
        points_.push_back(point);
        if (csv_ == nullptr) {
            return;
        }
        char wall[32];
        char gpu[32] = "";
        std::snprintf(wall, sizeof wall, "%.4f", point.measurement.wall_ms);
        if (point.measurement.gpu_ms) {
            std::snprintf(gpu, sizeof gpu, "%.4f", *point.measurement.gpu_ms);
        }
        const auto count = [](int value) { return value > 0 ? std::to_string(value) : ""; };
        *csv_ << scene::to_string(point.mode) << ',' << point.series << ',' << point.builder << ','
              << count(point.slices) << ',' << count(point.resolution) << ',' << width_ << ','
              << height_ << ',' << frames_ << ',' << wall << ',' << gpu << '\n';
        // Flushed per row so that an interrupted run still leaves what it measured.
        csv_->flush();
    }

    [[nodiscard]] const Measurement* find(scene::Mode mode, const std::string& series,
                                          int slices = 0, int resolution = 0) const {
        for (const auto& point : points_) {
            if (point.mode == mode && point.series == series && point.slices == slices &&
                point.resolution == resolution) {
                return &point.measurement;
            }
        }
        return nullptr;
    }

    [[nodiscard]] const Measurement* find_builder(scene::LightBufferBuilder builder, int slices,
                                                  int resolution) const {
        for (const auto& point : points_) {
            if (point.series == "light_buffer_pass" && point.builder == scene::to_string(builder) &&
                point.slices == slices && point.resolution == resolution) {
                return &point.measurement;
            }
        }
        return nullptr;
    }

private:
    std::ofstream* csv_;
    int width_;
    int height_;
    int frames_;
    std::vector<Point> points_;
};

// "      12.345       n/a": wall then gpu milliseconds.
std::string cells(const Measurement& m) {
    char text[48];
    if (m.gpu_ms) {
        std::snprintf(text, sizeof text, "%12.3f %9.3f", m.wall_ms, *m.gpu_ms);
    } else {
        std::snprintf(text, sizeof text, "%12.3f %9s", m.wall_ms, "n/a");
    }
    return text;
}

// a / b on wall times, with the gpu ratio alongside where both have one.
std::string ratio(const Measurement* a, const Measurement* b) {
    if (a == nullptr || b == nullptr || b->wall_ms <= 0.0) {
        return "n/a";
    }
    char text[64];
    if (a->gpu_ms && b->gpu_ms && *b->gpu_ms > 0.0) {
        std::snprintf(text, sizeof text, "%.2f (gpu %.2f)", a->wall_ms / b->wall_ms,
                      *a->gpu_ms / *b->gpu_ms);
    } else {
        std::snprintf(text, sizeof text, "%.2f", a->wall_ms / b->wall_ms);
    }
    return text;
}

bool contains(const std::vector<scene::Mode>& modes, scene::Mode mode) {
    return std::find(modes.begin(), modes.end(), mode) != modes.end();
}

int run_bench_modes(const std::vector<std::string>& args) {
    std::vector<std::string> valued = frame_option_names();
    valued.insert(valued.end(),
                  {"volume", "slices-list", "light-res-list", "repeat", "modes", "csv"});
    std::vector<std::string> flags = frame_flag_names();
    flags.insert(flags.end(), {"help", "debug-gl"});
    auto parsed = Arguments::parse(args, valued, flags);
    if (!parsed) {
        return usage_error(parsed.error());
    }
    if (parsed->has("help")) {
        print_modes_usage();
        return 0;
    }
    const Arguments& a = *parsed;
    // These three are what the benchmark sweeps; accepting one would silently ignore it.
    const std::pair<const char*, const char*> swept[] = {
            {"mode", "--modes"}, {"slices", "--slices-list"}, {"light-res", "--light-res-list"}};
    for (const auto& [option, instead] : swept) {
        if (a.has(option)) {
            return usage_error(base::make_error(
                    "invalid_argument",
                    std::string("bench modes sweeps this; use ") + instead + " LIST",
                    std::string("--") + option));
        }
    }
    auto slice_counts = parse_counts(a, "slices-list", "64,128,256");
    auto resolutions = parse_counts(a, "light-res-list", "128,256,512");
    auto modes = parse_modes(a.get("modes").value_or(scene::mode_names(",")));
    auto repeat = a.integer("repeat", 5);
    if (!slice_counts || !resolutions || !modes || !repeat) {
        return fail(!slice_counts  ? slice_counts.error()
                    : !resolutions ? resolutions.error()
                    : !modes       ? modes.error()
                                   : repeat.error());
    }
    if (*repeat < 1 || *repeat > 1000) {
        return fail(base::make_error("invalid_argument", "expects 1..1000", "--repeat"));
    }

    const std::string path = a.get("volume").value_or(default_volume_path);
    auto loaded = volume::load_volume(path);
    if (!loaded) {
        return fail(loaded.error());
    }
    auto volume = std::make_shared<const volume::Volume>(std::move(loaded.value()));
    auto base_request = frame_request_from(a, *volume);
    if (!base_request) {
        return fail(base_request.error());
    }
    std::ofstream csv;
    if (const auto csv_path = a.get("csv")) {
        csv.open(*csv_path);
        if (!csv) {
            return fail(base::make_error("io_error", "cannot write '" + *csv_path + "'", "--csv"));
        }
    }

    auto renderer =
            render::Renderer::create({.shader_dir = {}, .debug_context = a.has("debug-gl")});
    if (!renderer) {
        return fail(renderer.error());
    }
    if (auto status = (*renderer)->set_volume(volume); !status) {
        return fail(status.error());
    }
    ModeBench bench(**renderer, std::move(base_request.value()), *repeat);
    const scene::RenderSettings& s = bench.base().settings;
    Results results(csv.is_open() ? &csv : nullptr, s.width, s.height, *repeat);

    const render::RendererInfo& info = (*renderer)->info();
    std::printf("penumbra bench modes\n");
    std::printf("gl:       %s | %s | %s\n", info.renderer.c_str(), info.version.c_str(),
                info.platform.c_str());
    if (bench.gpu_timers()) {
        std::printf(
                "note:     absolute times mean something only on a GPU; compare the ratios "
                "across machines\n");
    } else {
        std::printf(
                "note:     software rasteriser (no GPU timer queries): absolute times mean "
                "something\n          only on a GPU; here read only the ratios\n");
    }
    std::printf("volume:   %s %ux%ux%u %s\n", volume->name.c_str(), volume->dims.x, volume->dims.y,
                volume->dims.z, volume::to_string(volume->type));
    std::printf(
            "frame:    %dx%d, tf %s, %s compositing, %s stage, sbrc builder %s, light lookup "
            "%s%s\n",
            s.width, s.height, bench.base().transfer_function.name.c_str(),
            scene::to_string(s.compositing), scene::to_string(s.stage),
            scene::to_string(s.light_buffer.builder), scene::to_string(s.light_buffer.lookup),
            s.phong ? ", phong" : "");
    std::printf(
            "timing:   per point 1 warm-up + %d timed frame(s), the camera orbiting %g deg a "
            "frame;\n          medians of the frame's summed pass wall_ms (gpu: summed timer "
            "queries)\n",
            *repeat, orbit_step_degrees);
    std::fflush(stdout);

    const auto record = [&](Point point, const scene::FrameRequest& request, LightBufferUse use,
                            const std::string& pass) -> base::Status {
        auto measured = bench.measure(point, request, use, pass);
        if (!measured) {
            return measured.error();
        }
        point.measurement = *measured;
        results.add(point);
        return base::Ok{};
    };
    const std::string builder_in_use = scene::to_string(s.light_buffer.builder);

    std::printf("\nframe time (ms)\n  %-11s %5s %5s %12s %9s\n", "mode", "n", "R", "wall", "gpu");
    for (const scene::ModeInfo& row : scene::modes()) {
        const scene::Mode mode = row.mode;
        if (!contains(*modes, mode) || mode == scene::Mode::half_angle ||
            scene::uses_light_buffer(mode)) {
            continue;
        }
        const Point point{mode, "frame", "", 0, 0, {}};
        if (auto status = record(point, bench.request(mode, 0, 0), LightBufferUse::none, {});
            !status) {
            return fail(status.error());
        }
        std::printf("  %-11s %5s %5s %s\n", scene::to_string(mode), "-", "-",
                    cells(*results.find(mode, "frame")).c_str());
        std::fflush(stdout);
    }
    if (contains(*modes, scene::Mode::half_angle)) {
        for (const int n : *slice_counts) {
            for (const int r : *resolutions) {
                const scene::Mode mode = scene::Mode::half_angle;
                const Point point{mode, "frame", "", n, r, {}};
                if (auto status =
                            record(point, bench.request(mode, n, r), LightBufferUse::none, {});
                    !status) {
                    return fail(status.error());
                }
                std::printf("  %-11s %5d %5d %s\n", scene::to_string(mode), n, r,
                            cells(*results.find(mode, "frame", n, r)).c_str());
                std::fflush(stdout);
            }
        }
    }

    bool any_light_buffer_mode = false;
    for (const scene::ModeInfo& row : scene::modes()) {
        const scene::Mode mode = row.mode;
        if (!scene::uses_light_buffer(mode) || !contains(*modes, mode)) {
            continue;
        }
        if (!any_light_buffer_mode) {
            any_light_buffer_mode = true;
            std::printf(
                    "\nlight-buffer modes (ms): cached = buffer reused, only the camera moves; "
                    "rebuild = the light\nmoves %g deg every frame, so the buffer is rebuilt "
                    "(builder %s)\n",
                    light_nudge_degrees, builder_in_use.c_str());
            std::printf("  %-11s %5s %5s %12s %9s %12s %9s  %s\n", "mode", "n", "R", "cached wall",
                        "gpu", "rebuild wall", "gpu", "rebuild/cached");
        }
        for (const int n : *slice_counts) {
            for (const int r : *resolutions) {
                const scene::FrameRequest request = bench.request(mode, n, r);
                const Point cached{mode, "cached", builder_in_use, n, r, {}};
                const Point rebuild{mode, "rebuild", builder_in_use, n, r, {}};
                if (auto status = record(cached, request, LightBufferUse::cached, {}); !status) {
                    return fail(status.error());
                }
                if (auto status = record(rebuild, request, LightBufferUse::rebuild, {}); !status) {
                    return fail(status.error());
                }
                const Measurement* c = results.find(mode, "cached", n, r);
                const Measurement* b = results.find(mode, "rebuild", n, r);
                std::printf("  %-11s %5d %5d %s %s  %s\n", scene::to_string(mode), n, r,
                            cells(*c).c_str(), cells(*b).c_str(), ratio(b, c).c_str());
                std::fflush(stdout);
            }
        }
    }

    if (any_light_buffer_mode) {
        std::printf(
                "\nlight-buffer builders (ms): the light_buffer pass alone, rebuilt every "
                "frame\n  %5s %5s %12s %9s %12s %9s  %s\n",
                "n", "R", "per_slice", "gpu", "multi_slice", "gpu", "per/multi");
        for (const int n : *slice_counts) {
            for (const int r : *resolutions) {
                for (const auto builder : builders) {
                    scene::FrameRequest request = bench.request(scene::Mode::sbrc, n, r);
                    request.settings.light_buffer.builder = builder;
                    const std::string name = scene::to_string(builder);
                    const Point point{scene::Mode::sbrc, "light_buffer_pass", name, n, r, {}};
                    if (auto status = record(point, request, LightBufferUse::rebuild,
                                             "light_buffer_" + name);
                        !status) {
                        return fail(status.error());
                    }
                }
                const Measurement* per_slice =
                        results.find_builder(scene::LightBufferBuilder::per_slice, n, r);
                const Measurement* multi_slice =
                        results.find_builder(scene::LightBufferBuilder::multi_slice, n, r);
                std::printf("  %5d %5d %s %s  %s\n", n, r, cells(*per_slice).c_str(),
                            cells(*multi_slice).c_str(), ratio(per_slice, multi_slice).c_str());
                std::fflush(stdout);
            }
        }
    }

    const int r_mid = (*resolutions)[resolutions->size() / 2];
    if (contains(*modes, scene::Mode::sbrc)) {
        std::printf(
                "\nlight lookups (ms): sbrc, light buffer cached, R=%d: the paper's interpolation "
                "between layers\nvs the local march through the last slab\n  %5s %12s %9s %12s "
                "%9s  %s\n",
                r_mid, "n", "interpolate", "gpu", "local", "gpu", "local/interpolate");
        for (const int n : *slice_counts) {
            for (const auto lookup : {scene::LightLookup::interpolate, scene::LightLookup::local}) {
                scene::FrameRequest request = bench.request(scene::Mode::sbrc, n, r_mid);
                request.settings.light_buffer.lookup = lookup;
                const Point point{scene::Mode::sbrc,
                                  std::string("lookup_") + scene::to_string(lookup),
                                  builder_in_use,
                                  n,
                                  r_mid,
                                  {}};
                if (auto status = record(point, request, LightBufferUse::cached, {}); !status) {
                    return fail(status.error());
                }
            }
            const Measurement* interpolate =
                    results.find(scene::Mode::sbrc, "lookup_interpolate", n, r_mid);
            const Measurement* local = results.find(scene::Mode::sbrc, "lookup_local", n, r_mid);
            std::printf("  %5d %s %s  %s\n", n, cells(*interpolate).c_str(), cells(*local).c_str(),
                        ratio(local, interpolate).c_str());
            std::fflush(stdout);
        }
    }

    const int n_min = *std::min_element(slice_counts->begin(), slice_counts->end());
    const int n_max = *std::max_element(slice_counts->begin(), slice_counts->end());
    std::printf("\nratios (of median wall times; gpu from timer queries where they work)\n");
    std::printf(
            "  half_angle / sbrc at equal n, R=%d (sbrc with its light buffer cached | "
            "rebuilt every frame | cached,\n  read with the paper's interpolating lookup):\n",
            r_mid);
    for (const int n : *slice_counts) {
        const Measurement* half_angle = results.find(scene::Mode::half_angle, "frame", n, r_mid);
        std::printf(
                "    n=%-5d cached %-22s rebuild %-22s interpolate %s\n", n,
                ratio(half_angle, results.find(scene::Mode::sbrc, "cached", n, r_mid)).c_str(),
                ratio(half_angle, results.find(scene::Mode::sbrc, "rebuild", n, r_mid)).c_str(),
                ratio(half_angle, results.find(scene::Mode::sbrc, "lookup_interpolate", n, r_mid))
                        .c_str());
    }
    std::printf(
            "  cached frame time at n=%d / at n=%d, R=%d (the paper: it barely grows with n; "
            "GPU target <= 1.20\n  from 64 to 256):\n",
            n_max, n_min, r_mid);
    for (const scene::ModeInfo& row : scene::modes()) {
        const scene::Mode mode = row.mode;
        if (!scene::uses_light_buffer(mode)) {
            continue;
        }
        std::printf("    %-11s %s\n", scene::to_string(mode),
                    ratio(results.find(mode, "cached", n_max, r_mid),
                          results.find(mode, "cached", n_min, r_mid))
                            .c_str());
    }
    std::printf(
            "  builder per_slice / multi_slice, the light_buffer pass alone, R=%d (GPU target "
            ">= 10 at n=256):\n",
            r_mid);
    for (const int n : *slice_counts) {
        std::printf("    n=%-5d %s\n", n,
                    ratio(results.find_builder(scene::LightBufferBuilder::per_slice, n, r_mid),
                          results.find_builder(scene::LightBufferBuilder::multi_slice, n, r_mid))
                            .c_str());
    }
    if (const auto csv_path = a.get("csv")) {
        std::printf("csv:      %s\n", csv_path->c_str());
    }
    return 0;
}

}  // namespace

// In cmd_bench_accuracy.cpp.
int run_bench_accuracy(const std::vector<std::string>& args);

int run_bench(const std::vector<std::string>& args) {
    if (args.empty()) {
        print_bench_usage();
        return 2;
    }
    if (args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
        print_bench_usage();
        return 0;
    }
    if (args[0] == "accuracy") {
        return run_bench_accuracy({args.begin() + 1, args.end()});
    }
    if (args[0] != "modes") {
        std::fprintf(stderr, "penumbra bench: unknown benchmark '%s'\n\n", args[0].c_str());
        print_bench_usage();
        return 2;
    }
    return run_bench_modes({args.begin() + 1, args.end()});
}

}  // namespace penumbra::app
