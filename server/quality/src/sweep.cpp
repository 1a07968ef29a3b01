// The sweep of the accuracy table (see the header).

#include "penumbra/quality/sweep.hpp"

#include <penumbra/encode/compare.hpp>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <utility>

namespace penumbra::quality {
namespace {

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
            frame->report.light_buffer != render::LightBufferState::reused) {
            return base::make_error(
                    "bench_invalid",
                    std::string(scene::to_string(request.settings.mode)) +
                            ": the light buffer was '" +
                            std::string(render::to_string(frame->report.light_buffer)) +
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
        if (frame->report.light_buffer != render::LightBufferState::built) {
            return base::make_error(
                    "bench_invalid",
                    "the light buffer was '" +
                            std::string(render::to_string(frame->report.light_buffer)) +
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

std::vector<SweepSetting> sweep_settings(const Sweep& sweep) {
    std::vector<SweepSetting> settings;
    for (const scene::Mode mode : sweep.modes) {
        if (mode != scene::Mode::half_angle && !scene::uses_light_buffer(mode)) {
            settings.push_back({mode, 0, 0});
        }
    }
    for (const int n : sweep.slices) {
        for (const int r : sweep.resolutions) {
            if (contains(sweep.modes, scene::Mode::half_angle) && half_angle_at(sweep, n, r)) {
                settings.push_back({scene::Mode::half_angle, n, r});
            }
            for (const scene::Mode mode : sweep.modes) {
                if (scene::uses_light_buffer(mode)) {
                    settings.push_back({mode, n, r});
                }
            }
        }
    }
    return settings;
}

scene::FrameRequest SweepSetting::applied(scene::FrameRequest request) const {
    request.settings.mode = mode;
    if (slices > 0) {
        request.settings.light_buffer.slices = slices;
        request.settings.light_buffer.resolution = resolution;
    }
    return request;
}

std::uint64_t frames_per_view(const Sweep& sweep) {
    const std::uint64_t per_point = static_cast<std::uint64_t>(sweep.repeat) + 1;
    const std::uint64_t distances = sweep.distances.size();
    std::uint64_t frames = distances * per_point;  // the references
    std::set<std::pair<int, int>> builds;          // one per light-buffer grid point
    for (const SweepSetting& setting : sweep_settings(sweep)) {
        frames += distances * per_point;
        if (scene::uses_light_buffer(setting.mode)) {
            builds.insert({setting.slices, setting.resolution});
        }
    }
    return frames + builds.size() * per_point;  // the builds, on tiny frames
}

namespace {

// The references at every sample distance, appended as points; false: the observer stopped.
base::Result<bool> measure_references(AccuracyBench& bench, const Sweep& sweep,
                                      const scene::FrameRequest& base, const std::string& volume,
                                      const LightAngles& light, const PointObserver& observer,
                                      std::vector<Point>& points,
                                      std::vector<base::ImageRgbaF>& references) {
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
    return true;
}

}  // namespace

base::Result<bool> measure_view(AccuracyBench& bench, const Sweep& sweep, scene::FrameRequest base,
                                const std::string& volume, const LightAngles& light,
                                const PointObserver& observer, std::vector<Point>& points) {
    base.light.type = scene::LightType::directional;
    base.light.direction = scene::direction_from_angles(light.azimuth, light.elevation);
    std::vector<base::ImageRgbaF> references;
    auto complete =
            measure_references(bench, sweep, base, volume, light, observer, points, references);
    if (!complete || !*complete) {
        return complete;
    }
    // The light-buffer modes build the same buffer (its key has no mode), so one build time per
    // grid point serves them all.
    std::map<std::pair<int, int>, double> builds;
    for (const SweepSetting& setting : sweep_settings(sweep)) {
        scene::FrameRequest request = setting.applied(base);
        double build_ms = 0.0;
        if (scene::uses_light_buffer(setting.mode)) {
            const std::pair<int, int> grid{setting.slices, setting.resolution};
            if (!builds.contains(grid)) {
                auto built = bench.light_buffer_build(request);
                if (!built) {
                    return built.error();
                }
                builds[grid] = *built;
            }
            build_ms = builds[grid];
        }
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
            const Point p{volume,
                          light,
                          setting.mode,
                          setting.slices,
                          setting.resolution,
                          sweep.distances[d],
                          timed->frame_ms,
                          build_ms,
                          same->rmse,
                          same->psnr,
                          same->ssim,
                          finest->rmse,
                          finest->psnr,
                          finest->ssim};
            points.push_back(p);
            if (!observer(p)) {
                return false;
            }
        }
    }
    return true;
}

}  // namespace penumbra::quality
