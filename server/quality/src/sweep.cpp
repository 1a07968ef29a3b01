// The sweep of the accuracy table (see the header).

#include "penumbra/quality/sweep.hpp"

#include <penumbra/encode/encode.hpp>
#include <penumbra/imageio/compare.hpp>
#include <penumbra/imageio/imageio.hpp>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <tuple>
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

// A light buffer's build: its grid point and whether its marches skip empty space.
using BuildKey = std::tuple<int, int, bool>;

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
    if (!imageio::available()) {
        constexpr double not_measured = std::numeric_limits<double>::quiet_NaN();
        return Errors{not_measured, not_measured, not_measured};
    }
    const base::ImageRgbaF rendered = base::to_rgba_f(image);
    auto difference = imageio::compare_images(reference, rendered);
    if (!difference) {
        return difference.error();
    }
    auto similarity = imageio::ssim(reference, rendered);
    if (!similarity) {
        return similarity.error();
    }
    return Errors{difference->rms_error, difference->psnr, *similarity};
}

std::string point_image_name(const Point& p) {
    std::string volume = p.volume;
    std::replace_if(
            volume.begin(), volume.end(),
            [](unsigned char c) { return std::isalnum(c) == 0 && c != '-'; }, '_');
    char light[64];
    std::snprintf(light, sizeof light, "-az%g-el%g-", p.light.azimuth, p.light.elevation);
    char grid[96];
    std::snprintf(grid, sizeof grid, "-n%d-r%d-d%.9g-", p.slices, p.resolution, p.sample_distance);
    return volume + light + std::string(scene::to_string(p.mode)) + grid +
           (p.empty_space_skipping ? "skip" : "noskip") + (p.jitter ? "-jitter" : "") + "-k" +
           std::to_string(p.refinement_steps) + ".png";
}

namespace {

// The point's image into the sweep's folder, where it has one.
base::Status keep_image(const Sweep& sweep, const Point& p, const base::ImageRgba8& image) {
    if (!sweep.images) {
        return base::Ok{};
    }
    return encode::write_image(*sweep.images / point_image_name(p), image);
}

}  // namespace

AccuracyBench::AccuracyBench(render::FrameRenderer& renderer, int repeat)
    : renderer_(renderer)
    , repeat_(repeat)
    , gpu_timers_(renderer.info().gpu_timer_queries) {}

double AccuracyBench::frame_time(const render::Frame& frame) const {
    double ms = 0.0;
    for (const auto& pass : frame.report.passes) {
        ms += gpu_timers_ ? std::max(pass.gpu_ms, 0.0) : pass.wall_ms;
    }
    return ms;
}

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
                    base::ErrorCode::bench_invalid,
                    std::string(scene::to_string(request.settings.mode)) +
                            ": the light buffer was '" +
                            std::string(render::to_string(frame->report.light_buffer)) +
                            "' in a repeat of the same request",
                    "light_buffer");
        }
        times.push_back(frame_time(*frame));
    }
    timed.frame_ms = median(times);
    return timed;
}

base::Result<std::vector<Timed>> AccuracyBench::refined(scene::FrameRequest request,
                                                        const std::vector<int>& steps) {
    std::vector<Timed> images;
    const int last = steps.empty() ? 0 : *std::max_element(steps.begin(), steps.end());
    request.refinement = {true, 0};
    if (auto still = render(request); !still) {
        return still.error();
    }
    std::vector<double> times;
    for (int step = 1; step <= last; ++step) {
        request.refinement = {false, step};
        auto frame = render(request);
        if (!frame) {
            return frame.error();
        }
        if (frame->report.refinement_step != step) {
            return base::make_error(base::ErrorCode::bench_invalid,
                                    "refinement step " + std::to_string(step) + " holds " +
                                            std::to_string(frame->report.refinement_step) +
                                            " steps",
                                    "refinement");
        }
        times.push_back(frame_time(*frame));
        if (contains(steps, step)) {
            images.push_back({std::move(frame->image), median(times)});
        }
    }
    return images;
}

base::Result<AccuracyBench::Converged> AccuracyBench::converged(scene::FrameRequest request,
                                                                int max_steps, double threshold) {
    const bool refines = scene::is_ray_cast(request.settings.mode) && request.settings.jitter;
    request.refinement = {};
    auto still = frame(request);
    if (!still) {
        return still.error();
    }
    Converged result{.still = *still, .last = std::move(*still)};
    std::optional<double> change;
    const int limit = refines ? max_steps : 0;
    while (scene::refines_after(result.steps, change, limit, threshold)) {
        // As a session refines (Scheduler): the steps at a finer step, averaged from the first.
        auto step = render(scene::refinement_step_request(request, result.steps + 1));
        if (!step) {
            return step.error();
        }
        auto changed = base::change_in_levels(result.last.image, step->image);
        if (!changed) {
            return changed.error();
        }
        change = *changed;
        ++result.steps;
        result.last_change = *change;
        result.last.frame_ms += frame_time(*step);
        result.last.image = std::move(step->image);
    }
    return result;
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
                    base::ErrorCode::bench_invalid,
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
            return base::make_error(base::ErrorCode::bench_invalid,
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
    // Every skipping and jitter of the sweep; a mode that casts no rays is never jittered.
    const auto add = [&](scene::Mode mode, int n, int r) {
        for (const bool skipping : sweep.skipping) {
            bool unjittered = false;
            for (const bool jitter : sweep.jitter) {
                const bool jittered = jitter && scene::is_ray_cast(mode);
                if (!jittered && unjittered) {
                    continue;
                }
                unjittered = unjittered || !jittered;
                settings.push_back({mode, n, r, skipping, jittered});
            }
        }
    };
    for (const scene::Mode mode : sweep.modes) {
        if (mode != scene::Mode::half_angle && !scene::uses_light_buffer(mode)) {
            add(mode, 0, 0);
        }
    }
    for (const int n : sweep.slices) {
        for (const int r : sweep.resolutions) {
            if (contains(sweep.modes, scene::Mode::half_angle) && half_angle_at(sweep, n, r)) {
                add(scene::Mode::half_angle, n, r);
            }
            for (const scene::Mode mode : sweep.modes) {
                if (scene::uses_light_buffer(mode)) {
                    add(mode, n, r);
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
    request.settings.empty_space_skipping = skipping;
    request.settings.jitter = jitter;
    return request;
}

int last_refinement_step(const Sweep& sweep) {
    return sweep.refinement_steps.empty() ? 0
                                          : *std::max_element(sweep.refinement_steps.begin(),
                                                              sweep.refinement_steps.end());
}

std::uint64_t frames_per_view(const Sweep& sweep) {
    const std::uint64_t per_point = static_cast<std::uint64_t>(sweep.repeat) + 1;
    const std::uint64_t distances = sweep.distances.size();
    std::uint64_t frames = distances * sweep.skipping.size() * per_point;  // the references
    std::set<BuildKey> builds;  // one per light-buffer grid point and skipping
    const std::uint64_t refinement = static_cast<std::uint64_t>(last_refinement_step(sweep));
    for (const SweepSetting& setting : sweep_settings(sweep)) {
        frames += distances * per_point;
        if (setting.jitter && refinement > 0) {
            frames += distances * (1 + refinement);  // the kept still and its steps
        }
        if (scene::uses_light_buffer(setting.mode)) {
            builds.insert({setting.slices, setting.resolution, setting.skipping});
        }
    }
    return frames + builds.size() * per_point;  // the builds, on tiny frames
}

namespace {

// The references at every sample distance, appended as points; false: the observer stopped.
// Without an explicit truth the first reference (the finest distance) is the truth.
base::Result<bool> measure_references(AccuracyBench& bench, const Sweep& sweep,
                                      const scene::FrameRequest& base, const std::string& volume,
                                      const LightAngles& light, const PointObserver& observer,
                                      const std::optional<base::ImageRgbaF>& truth,
                                      std::vector<Point>& points,
                                      std::vector<base::ImageRgbaF>& references) {
    for (const double distance : sweep.distances) {
        for (const bool skipping : sweep.skipping) {
            scene::FrameRequest request = base;
            request.settings.mode = scene::Mode::reference;
            request.settings.sample_distance = distance;
            request.settings.empty_space_skipping = skipping;
            request.settings.jitter = false;
            auto timed = bench.frame(request);
            if (!timed) {
                return timed.error();
            }
            const bool first_of_distance = skipping == sweep.skipping.front();
            if (first_of_distance) {
                references.push_back(base::to_rgba_f(timed->image));
            }
            Point p{.volume = volume,
                    .light = light,
                    .mode = scene::Mode::reference,
                    .sample_distance = distance,
                    .empty_space_skipping = skipping,
                    .frame_ms = timed->frame_ms,
                    .psnr = infinity,
                    .psnr_truth = infinity};
            // The reference of the other skipping (the same image, or nearly) is measured against
            // the first at its distance.
            if (!first_of_distance) {
                auto same = errors_against(references.back(), timed->image);
                if (!same) {
                    return same.error();
                }
                p.rmse = same->rmse;
                p.psnr = same->psnr;
                p.ssim = same->ssim;
            }
            const bool is_the_truth = !truth && first_of_distance && references.size() == 1;
            if (!is_the_truth) {
                auto against_truth =
                        errors_against(truth ? *truth : references.front(), timed->image);
                if (!against_truth) {
                    return against_truth.error();
                }
                p.rmse_truth = against_truth->rmse;
                p.psnr_truth = against_truth->psnr;
                p.ssim_truth = against_truth->ssim;
            }
            if (auto kept = keep_image(sweep, p, timed->image); !kept) {
                return kept.error();
            }
            points.push_back(p);
            if (!observer(p)) {
                return false;
            }
        }
    }
    return true;
}

}  // namespace

base::Result<bool> measure_view(AccuracyBench& bench, const Sweep& sweep, scene::FrameRequest base,
                                const std::string& volume, const LightAngles& light,
                                const PointObserver& observer, std::vector<Point>& points,
                                const TruthFor& truth) {
    base.light.type = scene::LightType::directional;
    base.light.direction = scene::direction_from_angles(light.azimuth, light.elevation);
    std::optional<base::ImageRgbaF> explicit_truth;
    if (truth) {
        auto image = truth(base);
        if (!image) {
            return image.error();
        }
        explicit_truth = base::to_rgba_f(*image);
    }
    std::vector<base::ImageRgbaF> references;
    auto complete = measure_references(bench, sweep, base, volume, light, observer, explicit_truth,
                                       points, references);
    if (!complete || !*complete) {
        return complete;
    }
    const base::ImageRgbaF& truth_image = explicit_truth ? *explicit_truth : references.front();
    // The light-buffer modes build the same buffer (its key has no mode), so one build time per
    // grid point serves them all.
    std::map<BuildKey, double> builds;
    for (const SweepSetting& setting : sweep_settings(sweep)) {
        scene::FrameRequest request = setting.applied(base);
        double build_ms = 0.0;
        if (scene::uses_light_buffer(setting.mode)) {
            const BuildKey grid{setting.slices, setting.resolution, setting.skipping};
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
            std::vector<std::pair<int, Timed>> images;
            images.emplace_back(0, std::move(*timed));
            if (setting.jitter && last_refinement_step(sweep) > 0) {
                auto refined = bench.refined(request, sweep.refinement_steps);
                if (!refined) {
                    return refined.error();
                }
                std::vector<int> steps = sweep.refinement_steps;
                std::sort(steps.begin(), steps.end());
                std::erase(steps, 0);
                steps.erase(std::unique(steps.begin(), steps.end()), steps.end());
                for (std::size_t i = 0; i < refined->size(); ++i) {
                    images.emplace_back(steps[i], std::move((*refined)[i]));
                }
            }
            for (const auto& [steps, image] : images) {
                auto same = errors_against(references[d], image.image);
                auto against_truth = errors_against(truth_image, image.image);
                if (!same || !against_truth) {
                    return !same ? same.error() : against_truth.error();
                }
                const Point p{.volume = volume,
                              .light = light,
                              .mode = setting.mode,
                              .slices = setting.slices,
                              .resolution = setting.resolution,
                              .sample_distance = sweep.distances[d],
                              .empty_space_skipping = setting.skipping,
                              .jitter = setting.jitter,
                              .refinement_steps = steps,
                              .frame_ms = image.frame_ms,
                              .light_buffer_ms = build_ms,
                              .rmse = same->rmse,
                              .psnr = same->psnr,
                              .ssim = same->ssim,
                              .rmse_truth = against_truth->rmse,
                              .psnr_truth = against_truth->psnr,
                              .ssim_truth = against_truth->ssim};
                if (auto kept = keep_image(sweep, p, image.image); !kept) {
                    return kept.error();
                }
                points.push_back(p);
                if (!observer(p)) {
                    return false;
                }
            }
        }
    }
    return true;
}

}  // namespace penumbra::quality
