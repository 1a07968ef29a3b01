#include "penumbra/bench/mode_bench.hpp"

#include <penumbra/quality/sweep.hpp>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace penumbra::bench {
namespace {

constexpr double point_light_nudge = 1e-4;  // world units; the volume's longest side is 1

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

}  // namespace

Orbit orbit_of(const scene::Camera& camera) {
    const glm::dvec3 offset = camera.eye - camera.target;
    const double distance = glm::length(offset);
    return {glm::degrees(std::atan2(offset.x, offset.y)),
            glm::degrees(std::asin(std::clamp(offset.z / distance, -1.0, 1.0))), distance,
            camera.target, camera.fov_y_degrees};
}

std::string point_label(const TimedPoint& point) {
    std::string label = scene::to_string(point.mode);
    if (point.slices > 0) {
        label += " n=" + std::to_string(point.slices) + " R=" + std::to_string(point.resolution);
    }
    if (!point.builder.empty() && point.series == "light_buffer_pass") {
        label += " builder " + point.builder;
    }
    return label;
}

namespace {

// The light-buffer state a timed frame of a series must report for the series to measure what
// its name says.
base::Status check_light_buffer(const TimedPoint& point, LightBufferUse use,
                                render::LightBufferState state) {
    const std::string light_buffer(render::to_string(state));
    if (use == LightBufferUse::cached && state != render::LightBufferState::reused) {
        return base::make_error(base::ErrorCode::bench_invalid,
                                point_label(point) + ": the light buffer was '" + light_buffer +
                                        "' in a frame where only the camera moved, so 'cached' "
                                        "would not measure reuse",
                                "light_buffer");
    }
    if (use == LightBufferUse::rebuild && state != render::LightBufferState::built) {
        return base::make_error(base::ErrorCode::bench_invalid,
                                point_label(point) + ": the light buffer was '" + light_buffer +
                                        "' in a frame whose light moved, so 'rebuild' would not "
                                        "measure a rebuild",
                                "light_buffer");
    }
    return base::Ok{};
}

struct PassTotal {
    double wall_ms = 0.0;
    double gpu_ms = 0.0;
    bool found = false;
};

// The frame's passes named `pass` summed; all of them where `pass` is empty.
PassTotal pass_total(const render::FrameReport& report, const std::string& pass) {
    PassTotal total;
    for (const auto& timing : report.passes) {
        if (pass.empty() || timing.name == pass) {
            total.found = true;
            total.wall_ms += timing.wall_ms;
            total.gpu_ms += std::max(timing.gpu_ms, 0.0);
        }
    }
    return total;
}

Measurement median_of(std::vector<double> wall, std::vector<double> gpu, bool gpu_timers) {
    Measurement measurement{quality::median(std::move(wall)), std::nullopt};
    if (gpu_timers) {
        measurement.gpu_ms = quality::median(std::move(gpu));
    }
    return measurement;
}

}  // namespace

base::Result<Measurement> ModeBench::measure(const TimedPoint& point, scene::FrameRequest request,
                                             LightBufferUse use, const std::string& pass) {
    auto series = measure_series(point, std::move(request), use, pass);
    if (!series) {
        return series.error();
    }
    return pass.empty() ? series->frame : *series->pass;
}

base::Result<Series> ModeBench::measure_series(const TimedPoint& point, scene::FrameRequest request,
                                               LightBufferUse use, const std::string& pass) {
    auto series = measure_interleaved({{point, std::move(request)}}, use, pass);
    if (!series) {
        return series.error();
    }
    return std::move(series->front());
}

base::Result<std::vector<Series>> ModeBench::measure_interleaved(
        std::vector<std::pair<TimedPoint, scene::FrameRequest>> variants, LightBufferUse use,
        const std::string& pass) {
    struct Samples {
        std::vector<double> frame_wall, frame_gpu, pass_wall, pass_gpu;
    };

    std::vector<Samples> samples(variants.size());
    std::vector<Series> series(variants.size());
    for (int i = 0; i <= repeat_; ++i) {
        for (std::size_t v = 0; v < variants.size(); ++v) {
            auto& [point, request] = variants[v];
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
            if (auto status = check_light_buffer(point, use, frame->report.light_buffer); !status) {
                return status.error();
            }
            const PassTotal whole = pass_total(frame->report, {});
            const PassTotal named = pass_total(frame->report, pass);
            if (!pass.empty() && !named.found) {
                return base::make_error(base::ErrorCode::bench_invalid,
                                        point_label(point) + ": no pass '" + pass +
                                                "' in a frame that rebuilt the light buffer",
                                        "light_buffer");
            }
            Samples& s = samples[v];
            s.frame_wall.push_back(whole.wall_ms);
            s.frame_gpu.push_back(whole.gpu_ms);
            s.pass_wall.push_back(named.wall_ms);
            s.pass_gpu.push_back(named.gpu_ms);
            series[v].last_image = std::move(frame->image);
        }
    }
    for (std::size_t v = 0; v < variants.size(); ++v) {
        Samples& s = samples[v];
        series[v].frame = median_of(std::move(s.frame_wall), std::move(s.frame_gpu), gpu_timers_);
        if (!pass.empty()) {
            series[v].pass = median_of(std::move(s.pass_wall), std::move(s.pass_gpu), gpu_timers_);
        }
    }
    return series;
}

}  // namespace penumbra::bench
