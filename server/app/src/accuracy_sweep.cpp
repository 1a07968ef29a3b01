// The measuring half of `penumbra bench accuracy`, shared with `penumbra serve` (see the header).

#include "accuracy_sweep.hpp"

#include "arguments.hpp"
#include "render_options.hpp"

#include <penumbra/encode/compare.hpp>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <utility>

namespace penumbra::app::accuracy {
namespace {

using Json = nlohmann::ordered_json;

constexpr const char* table_format = "penumbra-accuracy-1";

// Light-buffer builds are timed on frames this small: the buffer does not depend on the image size,
// and on a software rasteriser the ray cast of a full-size frame would cost more than the build.
constexpr int build_probe_side = 16;
// Small enough to leave the image unchanged, large enough to change the light buffer's key.
constexpr double light_nudge_degrees = 0.01;

bool contains(const std::vector<int>& values, int value) {
    return std::find(values.begin(), values.end(), value) != values.end();
}

bool contains(const std::vector<scene::Mode>& modes, scene::Mode mode) {
    return std::find(modes.begin(), modes.end(), mode) != modes.end();
}

// Whether half_angle is measured at n slices and resolution r of the grid.
bool half_angle_at(const Sweep& sweep, int n, int r) {
    return (sweep.half_angle_slices.empty() || contains(sweep.half_angle_slices, n)) &&
           (sweep.half_angle_resolutions.empty() || contains(sweep.half_angle_resolutions, r));
}

}  // namespace

double median(std::vector<double> values) {
    if (values.empty()) {
        return 0.0;
    }
    std::sort(values.begin(), values.end());
    const std::size_t middle = values.size() / 2;
    return values.size() % 2 == 1 ? values[middle] : 0.5 * (values[middle - 1] + values[middle]);
}

const char* timing_name(const Table& table) {
    return table.gpu_timers ? "gpu" : "wall";
}

Table make_table(const render::RendererInfo& info, int repeat, bool phong) {
    Table table;
    table.device = info.renderer;
    table.vendor = info.vendor;
    table.gl_version = info.version;
    table.gpu_timers = info.gpu_timer_queries;
    table.repeat = repeat;
    table.phong = phong;
    return table;
}

void describe_frame(Table& table, const scene::FrameRequest& base) {
    table.width = base.settings.width;
    table.height = base.settings.height;
    table.transfer_function = base.transfer_function.name;
    table.compositing = scene::to_string(base.settings.compositing);
    table.stage = scene::to_string(base.settings.stage);
    table.builder = scene::to_string(base.settings.light_buffer.builder);
    table.light_lookup = scene::to_string(base.settings.light_buffer.lookup);
    table.slab_samples = base.settings.light_buffer.slab_samples;
    table.camera = base.camera;
}

std::vector<Setting> aggregate(const std::vector<Point>& points,
                               const std::optional<std::string>& volume) {
    std::map<SettingKey, Setting> settings;
    for (const Point& p : points) {
        if (volume && p.volume != *volume) {
            continue;
        }
        const SettingKey key{p.mode, p.slices, p.resolution, p.sample_distance};
        Setting& s = settings[key];
        s.key = key;
        ++s.count;
        s.psnr += p.psnr;
        s.ssim += p.ssim;
        s.psnr_finest += p.psnr_finest;
        s.ssim_finest += p.ssim_finest;
        s.frame_ms += p.frame_ms;
        s.worst_frame_ms = std::max(s.worst_frame_ms, p.frame_ms);
        s.light_buffer_ms += p.light_buffer_ms;
    }
    std::vector<Setting> result;
    for (auto& [key, s] : settings) {
        const double n = static_cast<double>(s.count);
        s.psnr /= n;
        s.ssim /= n;
        s.psnr_finest /= n;
        s.ssim_finest /= n;
        s.frame_ms /= n;
        s.light_buffer_ms /= n;
        result.push_back(s);
    }
    return result;
}

bool more_accurate(const Setting& a, const Setting& b) {
    if (a.psnr_finest != b.psnr_finest) {
        return a.psnr_finest > b.psnr_finest;
    }
    if (a.ssim_finest != b.ssim_finest) {
        return a.ssim_finest > b.ssim_finest;
    }
    return a.worst_frame_ms < b.worst_frame_ms;
}

std::vector<Preset> choose_presets(const std::vector<Point>& points,
                                   const std::vector<double>& budgets) {
    std::set<std::pair<std::string, LightAngles>> views;
    for (const Point& p : points) {
        views.insert({p.volume, p.light});
    }
    const int complete = static_cast<int>(views.size());
    std::vector<Setting> candidates;
    for (const Setting& s : aggregate(points)) {
        if (s.count == complete) {
            candidates.push_back(s);
        }
    }
    std::sort(candidates.begin(), candidates.end(), more_accurate);
    std::vector<Preset> presets;
    for (const double budget : budgets) {
        Preset preset{budget, std::nullopt};
        for (const Setting& s : candidates) {
            if (s.worst_frame_ms <= budget) {
                preset.setting = s;
                break;
            }
        }
        presets.push_back(preset);
    }
    return presets;
}

// Six budgets from the fastest setting to the slowest reference, evenly spaced in log time and
// rounded up to two significant digits: past the reference's time the answer is always the
// reference, so budgets beyond it say nothing.
std::vector<double> default_budgets(const std::vector<Point>& points) {
    const std::vector<Setting> settings = aggregate(points);
    if (settings.empty()) {
        return {};
    }
    double low = infinity;
    double slowest = 0.0;
    double reference = 0.0;
    for (const Setting& s : settings) {
        low = std::min(low, s.worst_frame_ms);
        slowest = std::max(slowest, s.worst_frame_ms);
        if (s.key.mode == scene::Mode::reference) {
            reference = std::max(reference, s.worst_frame_ms);
        }
    }
    double high = reference > 0.0 ? reference : slowest;
    high *= 1.05;
    low = std::max(low, 1e-3);
    std::vector<double> budgets;
    constexpr int count = 6;
    for (int i = 0; i < count; ++i) {
        const double t = static_cast<double>(i) / (count - 1);
        const double value = low * std::pow(high / low, t);
        const double magnitude = std::pow(10.0, std::floor(std::log10(value)) - 1.0);
        const double rounded = std::ceil(value / magnitude) * magnitude;
        if (budgets.empty() || rounded > budgets.back()) {
            budgets.push_back(rounded);
        }
    }
    return budgets;
}

namespace {

// JSON has no infinity: an identical image's PSNR is null.
Json psnr_json(double psnr) {
    return std::isinf(psnr) ? Json(nullptr) : Json(psnr);
}

double psnr_from_json(const Json& value) {
    return value.is_null() ? infinity : value.get<double>();
}

Json camera_json(const scene::Camera& c) {
    return {{"eye", {c.eye.x, c.eye.y, c.eye.z}},
            {"target", {c.target.x, c.target.y, c.target.z}},
            {"up", {c.up.x, c.up.y, c.up.z}},
            {"fov_y_degrees", c.fov_y_degrees}};
}

scene::Camera camera_from_json(const Json& value) {
    const auto vec3 = [](const Json& v) {
        return glm::dvec3(v.at(0).get<double>(), v.at(1).get<double>(), v.at(2).get<double>());
    };
    scene::Camera camera;
    camera.eye = vec3(value.at("eye"));
    camera.target = vec3(value.at("target"));
    camera.up = vec3(value.at("up"));
    camera.fov_y_degrees = value.at("fov_y_degrees").get<double>();
    return camera;
}

Json to_json(const Table& table, const std::vector<Preset>& presets) {
    Json root;
    root["format"] = table_format;
    root["description"] =
            "Accuracy vs frame time of Penumbra's rendering modes (penumbra bench accuracy). "
            "points: one per volume x light x mode x setting; rmse/psnr/ssim against the "
            "reference mode (shadow rays) at the same sample distance and camera, *_finest "
            "against the reference at the finest sample distance; psnr null = identical "
            "(infinite). frame_ms: median frame time with the light buffer cached; "
            "light_buffer_ms: median light-buffer build, 0 where the mode builds none. slices "
            "and resolution 0 where the mode has none. presets: per budget_ms, the setting with "
            "the highest mean psnr_finest over all volumes and lights whose slowest frame_ms "
            "fits (mode null: none fits).";
    root["device"] = table.device;
    root["renderer"] = {{"vendor", table.vendor},
                        {"version", table.gl_version},
                        {"gpu_timer_queries", table.gpu_timers}};
    root["timing"] = timing_name(table);
    root["size"] = {table.width, table.height};
    root["settings"] = {{"transfer_function", table.transfer_function},
                        {"compositing", table.compositing},
                        {"stage", table.stage},
                        {"builder", table.builder},
                        {"light_lookup", table.light_lookup},
                        {"slab_samples", table.slab_samples},
                        {"phong", table.phong},
                        {"repeat", table.repeat},
                        {"camera", camera_json(table.camera)}};
    Json points = Json::array();
    for (const Point& p : table.points) {
        points.push_back({{"volume", p.volume},
                          {"light", {p.light.azimuth, p.light.elevation}},
                          {"mode", scene::to_string(p.mode)},
                          {"slices", p.slices},
                          {"resolution", p.resolution},
                          {"sample_distance", p.sample_distance},
                          {"frame_ms", p.frame_ms},
                          {"light_buffer_ms", p.light_buffer_ms},
                          {"rmse", p.rmse},
                          {"psnr", psnr_json(p.psnr)},
                          {"ssim", p.ssim},
                          {"rmse_finest", p.rmse_finest},
                          {"psnr_finest", psnr_json(p.psnr_finest)},
                          {"ssim_finest", p.ssim_finest}});
    }
    root["points"] = std::move(points);
    Json preset_list = Json::array();
    for (const Preset& preset : presets) {
        if (!preset.setting) {
            preset_list.push_back({{"budget_ms", preset.budget_ms}, {"mode", nullptr}});
            continue;
        }
        const Setting& s = *preset.setting;
        preset_list.push_back({{"budget_ms", preset.budget_ms},
                               {"mode", scene::to_string(s.key.mode)},
                               {"slices", s.key.slices},
                               {"resolution", s.key.resolution},
                               {"sample_distance", s.key.sample_distance},
                               {"psnr", psnr_json(s.psnr_finest)},
                               {"ssim", s.ssim_finest},
                               {"frame_ms", s.worst_frame_ms},
                               {"light_buffer_ms", s.light_buffer_ms}});
    }
    root["presets"] = std::move(preset_list);
    return root;
}

}  // namespace

std::string table_json(const Table& table, const std::vector<Preset>& presets) {
    return to_json(table, presets).dump(1);
}

base::Status write_json(const Table& table, const std::vector<Preset>& presets,
                        const std::string& path, const std::string& option) {
    std::ofstream out(path);
    if (!out) {
        return base::make_error("io_error", "cannot write '" + path + "'", option);
    }
    out << table_json(table, presets) << '\n';
    if (!out) {
        return base::make_error("io_error", "writing '" + path + "' failed", option);
    }
    return base::Ok{};
}

base::Result<Table> read_table(const std::string& path, const std::string& option) {
    std::ifstream in(path);
    if (!in) {
        return base::make_error("io_error", "cannot read '" + path + "'", option);
    }
    try {
        const Json root = Json::parse(in);
        if (root.value("format", "") != table_format) {
            return base::make_error("invalid_table",
                                    "not a table written by `bench accuracy --json` (format " +
                                            std::string(table_format) + ")",
                                    path);
        }
        Table table;
        table.device = root.at("device").get<std::string>();
        const Json& renderer = root.at("renderer");
        table.vendor = renderer.at("vendor").get<std::string>();
        table.gl_version = renderer.at("version").get<std::string>();
        table.gpu_timers = renderer.at("gpu_timer_queries").get<bool>();
        table.width = root.at("size").at(0).get<int>();
        table.height = root.at("size").at(1).get<int>();
        const Json& settings = root.at("settings");
        table.transfer_function = settings.at("transfer_function").get<std::string>();
        table.compositing = settings.at("compositing").get<std::string>();
        table.stage = settings.at("stage").get<std::string>();
        table.builder = settings.at("builder").get<std::string>();
        // Tables written before these settings existed were measured the paper's way.
        table.light_lookup = settings.value("light_lookup", std::string("interpolate"));
        table.slab_samples = settings.value("slab_samples", 1);
        table.phong = settings.at("phong").get<bool>();
        table.repeat = settings.at("repeat").get<int>();
        table.camera = camera_from_json(settings.at("camera"));
        for (const Json& item : root.at("points")) {
            Point p;
            p.volume = item.at("volume").get<std::string>();
            p.light = {item.at("light").at(0).get<double>(), item.at("light").at(1).get<double>()};
            const auto mode = scene::parse_mode(item.at("mode").get<std::string>());
            if (!mode) {
                return base::make_error("invalid_table", "unknown mode", path);
            }
            p.mode = *mode;
            p.slices = item.at("slices").get<int>();
            p.resolution = item.at("resolution").get<int>();
            p.sample_distance = item.at("sample_distance").get<double>();
            p.frame_ms = item.at("frame_ms").get<double>();
            p.light_buffer_ms = item.at("light_buffer_ms").get<double>();
            p.rmse = item.at("rmse").get<double>();
            p.psnr = psnr_from_json(item.at("psnr"));
            p.ssim = item.at("ssim").get<double>();
            p.rmse_finest = item.at("rmse_finest").get<double>();
            p.psnr_finest = psnr_from_json(item.at("psnr_finest"));
            p.ssim_finest = item.at("ssim_finest").get<double>();
            table.points.push_back(std::move(p));
        }
        return table;
    } catch (const Json::exception& e) {
        return base::make_error("invalid_table", e.what(), path);
    }
}

base::Result<Errors> errors_against(const base::ImageRgbaF& reference,
                                    const base::ImageRgba8& image) {
    const base::ImageRgbaF rendered = base::to_rgba_f(image);
    auto difference = encode::compare_images(reference, rendered);
    if (!difference) {
        return difference.error();
    }
    auto similarity = encode::ssim(reference, rendered);
    if (!similarity) {
        return similarity.error();
    }
    return Errors{difference->rms_error, difference->psnr, *similarity};
}

AccuracyBench::AccuracyBench(render::FrameRenderer& renderer, int repeat)
    : renderer_(renderer)
    , repeat_(repeat)
    , gpu_timers_(renderer.info().gpu_timer_queries) {}

base::Result<Timed> AccuracyBench::frame(const scene::FrameRequest& request) {
    Timed timed;
    std::vector<double> times;
    for (int i = 0; i <= repeat_; ++i) {
        auto frame = render(request);
        if (!frame) {
            return frame.error();
        }
        if (i == 0) {
            timed.image = std::move(frame->image);
            continue;
        }
        if (scene::uses_light_buffer(request.settings.mode) &&
            frame->report.light_buffer != "reused") {
            return base::make_error("bench_invalid",
                                    std::string(scene::to_string(request.settings.mode)) +
                                            ": the light buffer was '" +
                                            frame->report.light_buffer +
                                            "' in a repeat of the same request",
                                    "light_buffer");
        }
        double ms = 0.0;
        for (const auto& pass : frame->report.passes) {
            ms += gpu_timers_ ? std::max(pass.gpu_ms, 0.0) : pass.wall_ms;
        }
        times.push_back(ms);
    }
    timed.frame_ms = median(times);
    return timed;
}

base::Result<double> AccuracyBench::light_buffer_build(scene::FrameRequest request) {
    request.settings.width = build_probe_side;
    request.settings.height = build_probe_side;
    const glm::dvec3 direction = request.light.direction;
    const glm::dvec3 axis =
            std::abs(direction.z) > 0.999 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 0.0, 1.0);
    // Every frame gets a light not used before: the renderer caches light buffers by their
    // inputs, so an earlier light would reuse its buffer instead of building one.
    const auto nudged = [&](std::uint64_t k) {
        const double angle = glm::radians(light_nudge_degrees * static_cast<double>(k % 4096));
        return direction * std::cos(angle) + glm::cross(axis, direction) * std::sin(angle) +
               axis * glm::dot(axis, direction) * (1.0 - std::cos(angle));
    };
    const std::string pass_name =
            std::string("light_buffer_") + scene::to_string(request.settings.light_buffer.builder);
    std::vector<double> times;
    for (int i = 0; i <= repeat_; ++i) {
        request.light.direction = nudged(++nudges_);
        auto frame = render(request);
        if (!frame) {
            return frame.error();
        }
        if (frame->report.light_buffer != "built") {
            return base::make_error("bench_invalid",
                                    "the light buffer was '" + frame->report.light_buffer +
                                            "' in a frame whose light moved",
                                    "light_buffer");
        }
        if (i == 0) {
            continue;  // warm-up: the builder's shaders compile here
        }
        double ms = -1.0;
        for (const auto& pass : frame->report.passes) {
            if (pass.name == pass_name) {
                ms = gpu_timers_ ? std::max(pass.gpu_ms, 0.0) : pass.wall_ms;
            }
        }
        if (ms < 0.0) {
            return base::make_error("bench_invalid",
                                    "no pass '" + pass_name + "' in a rebuilding frame",
                                    "light_buffer");
        }
        times.push_back(ms);
    }
    return median(times);
}

base::Result<render::Frame> AccuracyBench::render(const scene::FrameRequest& request) {
    ++frames_;
    return renderer_.render(request);
}

std::uint64_t frames_per_view(const Sweep& sweep) {
    const std::uint64_t per_point = static_cast<std::uint64_t>(sweep.repeat) + 1;
    const std::uint64_t grid = sweep.slices.size() * sweep.resolutions.size();
    std::uint64_t half_angle_grid = 0;
    for (const int n : sweep.slices) {
        for (const int r : sweep.resolutions) {
            half_angle_grid += half_angle_at(sweep, n, r) ? 1 : 0;
        }
    }
    const std::uint64_t distances = sweep.distances.size();
    std::uint64_t frames = distances * per_point;  // the references
    bool any_light_buffer = false;
    for (const scene::Mode mode : sweep.modes) {
        if (scene::uses_light_buffer(mode)) {
            any_light_buffer = true;
            frames += grid * distances * per_point;
        } else if (mode == scene::Mode::half_angle) {
            frames += half_angle_grid * distances * per_point;
        } else {
            frames += distances * per_point;
        }
    }
    if (any_light_buffer) {
        frames += grid * per_point;  // the builds, on tiny frames
    }
    return frames;
}

base::Result<bool> measure_view(AccuracyBench& bench, const Sweep& sweep, scene::FrameRequest base,
                                const std::string& volume, const LightAngles& light,
                                const PointObserver& observer, std::vector<Point>& points) {
    base.light.type = scene::LightType::directional;
    base.light.direction = scene::direction_from_angles(light.azimuth, light.elevation);

    std::vector<base::ImageRgbaF> references;
    for (const double distance : sweep.distances) {
        scene::FrameRequest request = base;
        request.settings.mode = scene::Mode::reference;
        request.settings.sample_distance = distance;
        auto timed = bench.frame(request);
        if (!timed) {
            return timed.error();
        }
        references.push_back(base::to_rgba_f(timed->image));
        Point p{volume,
                light,
                scene::Mode::reference,
                0,
                0,
                distance,
                timed->frame_ms,
                0.0,
                0.0,
                infinity,
                1.0,
                0.0,
                infinity,
                1.0};
        if (references.size() > 1) {
            auto finest = errors_against(references.front(), timed->image);
            if (!finest) {
                return finest.error();
            }
            p.rmse_finest = finest->rmse;
            p.psnr_finest = finest->psnr;
            p.ssim_finest = finest->ssim;
        }
        points.push_back(p);
        if (!observer(p)) {
            return false;
        }
    }

    // Renders one point at every sample distance and records it; false: the observer stopped.
    const auto record = [&](scene::FrameRequest request, int slices, int resolution,
                            double build_ms) -> base::Result<bool> {
        for (std::size_t d = 0; d < sweep.distances.size(); ++d) {
            request.settings.sample_distance = sweep.distances[d];
            auto timed = bench.frame(request);
            if (!timed) {
                return timed.error();
            }
            auto same = errors_against(references[d], timed->image);
            auto finest = errors_against(references.front(), timed->image);
            if (!same || !finest) {
                return !same ? same.error() : finest.error();
            }
            const Point p{volume,          light,       request.settings.mode,
                          slices,          resolution,  sweep.distances[d],
                          timed->frame_ms, build_ms,    same->rmse,
                          same->psnr,      same->ssim,  finest->rmse,
                          finest->psnr,    finest->ssim};
            points.push_back(p);
            if (!observer(p)) {
                return false;
            }
        }
        return true;
    };

    for (const scene::Mode mode : sweep.modes) {
        if (mode == scene::Mode::half_angle || scene::uses_light_buffer(mode)) {
            continue;
        }
        scene::FrameRequest request = base;
        request.settings.mode = mode;
        auto going_on = record(request, 0, 0, 0.0);
        if (!going_on || !*going_on) {
            return going_on;
        }
    }
    for (const int n : sweep.slices) {
        for (const int r : sweep.resolutions) {
            scene::FrameRequest request = base;
            request.settings.light_buffer.slices = n;
            request.settings.light_buffer.resolution = r;
            if (contains(sweep.modes, scene::Mode::half_angle) && half_angle_at(sweep, n, r)) {
                request.settings.mode = scene::Mode::half_angle;
                auto going_on = record(request, n, r, 0.0);
                if (!going_on || !*going_on) {
                    return going_on;
                }
            }
            // The three light-buffer modes build the same buffer (its key has no mode), so one
            // build time serves them all.
            std::optional<double> build_ms;
            for (const scene::Mode mode : sweep.modes) {
                if (!scene::uses_light_buffer(mode)) {
                    continue;
                }
                request.settings.mode = mode;
                if (!build_ms) {
                    auto built = bench.light_buffer_build(request);
                    if (!built) {
                        return built.error();
                    }
                    build_ms = *built;
                }
                auto going_on = record(request, n, r, *build_ms);
                if (!going_on || !*going_on) {
                    return going_on;
                }
            }
        }
    }
    return true;
}

StartupOptions startup_options() {
    StartupOptions options;
    Sweep& sweep = options.sweep;
    sweep.lights = {{10.0, 45.0}};
    sweep.modes = {scene::Mode::phong, scene::Mode::half_angle, scene::Mode::sbrc,
                   scene::Mode::sbrc_cone};
    sweep.slices = {64, 128, 256};
    sweep.resolutions = {128, 256};
    sweep.half_angle_slices = {64, 128};
    sweep.half_angle_resolutions = {128};
    sweep.distances = {1.0 / 256.0};
    sweep.repeat = 3;
    return options;
}

base::Result<StartupTable> measure_startup_table(render::FrameRenderer& renderer,
                                                 std::shared_ptr<const volume::Volume> volume,
                                                 const StartupOptions& options) {
    using Clock = std::chrono::steady_clock;
    const Clock::time_point start = Clock::now();
    const auto seconds = [&] {
        return std::chrono::duration<double>(Clock::now() - start).count();
    };
    if (options.side < min_image_side) {
        return base::make_error("invalid_argument",
                                "SSIM needs images of at least " + std::to_string(min_image_side) +
                                        "x" + std::to_string(min_image_side),
                                "side");
    }
    // The defaults of `penumbra render` and `bench accuracy`: the camera, TF and lighting the
    // committed tables were measured with.
    auto no_options = Arguments::parse({}, frame_option_names(), frame_flag_names());
    if (!no_options) {
        return no_options.error();
    }
    auto request = frame_request_from(*no_options, *volume);
    if (!request) {
        return request.error();
    }
    request->settings.width = options.side;
    request->settings.height = options.side;
    request->settings.phong = true;

    StartupTable result;
    result.table = make_table(renderer.info(), options.sweep.repeat, true);
    describe_frame(result.table, *request);
    if (auto status = renderer.set_volume(volume); !status) {
        return status.error();
    }
    AccuracyBench bench(renderer, options.sweep.repeat);
    const PointObserver within_limit = [&](const Point&) {
        return seconds() < options.time_limit_s;
    };
    for (const LightAngles& light : options.sweep.lights) {
        auto complete = measure_view(bench, options.sweep, *request, volume->name, light,
                                     within_limit, result.table.points);
        if (!complete) {
            return complete.error();
        }
        if (!*complete) {
            result.complete = false;
            break;
        }
    }
    result.seconds = seconds();
    return result;
}

}  // namespace penumbra::app::accuracy
