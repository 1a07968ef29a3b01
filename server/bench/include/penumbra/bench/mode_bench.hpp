#pragma once

// The measuring half of `penumbra bench modes`: frame times of each rendering mode side by side,
// the light buffer cached against rebuilt, one pass alone; each series checks that its frames did
// what its name says (a cached series that rebuilt the buffer would measure the wrong thing).

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::bench {

// Every frame of a series sees a new view, as a user dragging the camera would, while the work
// per frame stays comparable from one frame to the next.
inline constexpr double orbit_step_degrees = 2.0;
// Small enough to leave the image unchanged, large enough to change the light buffer's key.
inline constexpr double light_nudge_degrees = 0.01;

// The median cost of one frame (or of one pass) over a series.
struct Measurement {
    double wall_ms = 0.0;
    std::optional<double> gpu_ms;  // absent where the GL's timer queries mean nothing
};

// A series measured as whole frames and, where a pass was named, as that pass alone; with the
// image of its last frame, which every series of the same length draws from the same view.
struct Series {
    Measurement frame;
    std::optional<Measurement> pass;
    base::ImageRgba8 last_image;
};

// What a series does to the light buffer between its timed frames, and so what each of those
// frames must report for the series to measure what its name says.
enum class LightBufferUse { none, cached, rebuild };

struct TimedPoint {
    scene::Mode mode = scene::Mode::dvr;
    std::string series;   // "frame", "cached", "rebuild" or "light_buffer_pass"
    std::string builder;  // empty where no light buffer is built
    int slices = 0;       // 0 where the mode does not depend on it
    int resolution = 0;
    Measurement measurement;
};

// "sbrc n=64 R=128", with the builder for a light_buffer_pass series.
std::string point_label(const TimedPoint& point);

// The azimuth, elevation and distance that reproduce a camera with scene::orbit_camera.
struct Orbit {
    double azimuth = 0.0;
    double elevation = 0.0;
    double distance = 1.0;
    glm::dvec3 target{0.0};
    double fov_y_degrees = 30.0;
};

// The camera a ModeBench orbits from.
Orbit orbit_of(const scene::Camera& camera);

class ModeBench {
public:
    ModeBench(render::FrameRenderer& renderer, scene::FrameRequest base, int repeat)
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
    base::Result<Measurement> measure(const TimedPoint& point, scene::FrameRequest request,
                                      LightBufferUse use, const std::string& pass = {});

    // As measure, timing the whole frame and `pass` (if named) from the same frames.
    base::Result<Series> measure_series(const TimedPoint& point, scene::FrameRequest request,
                                        LightBufferUse use, const std::string& pass = {});

    // As measure_series for each variant, their frames taken in turn (each camera of the orbit
    // drawn by every variant before the next), so that a drift of the machine's speed during the
    // run weighs on all of them alike and their ratios hold.
    base::Result<std::vector<Series>> measure_interleaved(
            std::vector<std::pair<TimedPoint, scene::FrameRequest>> variants, LightBufferUse use,
            const std::string& pass = {});

    // How many timed frames each series takes.
    [[nodiscard]] int repeat() const { return repeat_; }

private:
    render::FrameRenderer& renderer_;
    scene::FrameRequest base_;
    Orbit orbit_;
    int repeat_;
    std::uint64_t nudges_ = 0;  // distinct lights the rebuild frames have used so far
    bool gpu_timers_;
};

// The sweep's results, looked up again for the ratios and written to the CSV as they come.
class TimedResults {
public:
    explicit TimedResults(std::ostream* csv, int width, int height, int frames)
        : csv_(csv)
        , width_(width)
        , height_(height)
        , frames_(frames) {
        if (csv_ != nullptr) {
            *csv_ << "mode,series,builder,slices,light_res,width,height,frames,wall_ms,gpu_ms\n";
        }
    }

    void add(const TimedPoint& point) {
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
    std::ostream* csv_;
    int width_;
    int height_;
    int frames_;
    std::vector<TimedPoint> points_;
};

}  // namespace penumbra::bench
