#pragma once

// The measuring half of the accuracy table: renders every point of a sweep against the
// `reference` mode of the same sample distance and against the truth, and times it. `penumbra
// serve` measures a short sweep at start-up (startup.hpp), `penumbra bench accuracy` one from its
// options over several volumes.

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/quality/table.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/volume/volume.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::quality {

// The SSIM window is 11 pixels; a little margin keeps the valid region from being one window.
inline constexpr int min_image_side = 16;

double median(std::vector<double> values);

// A table of this renderer, to be measured with `repeat` timed frames per point.
Table make_table(const render::RendererInfo& info, int repeat, bool phong);

// Records the frame every point of the table shares (size, TF, compositing, camera...).
void describe_frame(Table& table, const scene::FrameRequest& base);

struct Timed {
    base::ImageRgba8 image;
    double frame_ms = 0.0;
};

struct Errors {
    double rmse = 0.0;
    double psnr = 0.0;
    double ssim = 1.0;
};

// RMSE and PSNR over RGB, SSIM on luma; NaN each (not measured) in a build without image
// comparison (imageio::available()), where a sweep only times its frames.
base::Result<Errors> errors_against(const base::ImageRgbaF& reference,
                                    const base::ImageRgba8& image);

// Renders and times frames on one renderer, which must be used on the thread that created it.
class AccuracyBench {
public:
    AccuracyBench(render::FrameRenderer& renderer, int repeat);

    [[nodiscard]] std::uint64_t frames() const { return frames_; }

    // One warm-up frame (compiles the variant, builds the light buffer), whose image is the one
    // judged, then `repeat` frames of the same request timed. The timed frames must reuse the light
    // buffer, or the time would not be the camera-move cost it claims to be.
    base::Result<Timed> frame(const scene::FrameRequest& request);

    // A progressive still: `request` (jittered) kept, then refinement steps up to the largest of
    // `steps`; the running mean after each count in `steps`, with the median time of the step
    // frames so far (each step is timed once: a step changes what the next one averages into).
    base::Result<std::vector<Timed>> refined(scene::FrameRequest request,
                                             const std::vector<int>& steps);

    // A still as a session refines it: `request` (jittered; its refinement is replaced) timed as
    // frame() times it, then refinement steps, each timed once, until scene::refines_after stops
    // them at `max_steps` or at a step that changed the image by `threshold` or less.
    struct Converged {
        Timed still;             // the first still, its median time
        Timed last;              // the last step's image, the still's time plus every step's
        int steps = 0;           // refinement steps after the still
        double last_change = 0;  // the last step's change, RMS in 8-bit levels (0 with no step)
    };

    base::Result<Converged> converged(scene::FrameRequest request, int max_steps, double threshold);

    // The light-buffer pass alone, rebuilt every frame by nudging the light to and fro, on tiny
    // frames (the buffer does not depend on the image size).
    base::Result<double> light_buffer_build(scene::FrameRequest request);

private:
    base::Result<render::Frame> render(const scene::FrameRequest& request);

    // The frame's passes: GPU time where the timers work, else wall clock.
    [[nodiscard]] double frame_time(const render::Frame& frame) const;

    render::FrameRenderer& renderer_;
    int repeat_;
    std::uint64_t nudges_ = 0;  // distinct lights used by build measurements so far
    bool gpu_timers_;
    std::uint64_t frames_ = 0;
};

// What to sweep: plain lists, so that a new dimension is a new list and its loop.
struct Sweep {
    std::vector<std::string> volumes;
    std::vector<LightAngles> lights;
    std::vector<scene::Mode> modes;  // never the reference, which is always rendered
    std::vector<int> slices;
    std::vector<int> resolutions;
    // half_angle only at these of `slices` and `resolutions`; empty: at all of them. Its
    // slicing costs more per slice than a light-buffer lookup, so a short sweep trims it.
    std::vector<int> half_angle_slices;
    std::vector<int> half_angle_resolutions;
    std::vector<double> distances;  // finest first
    // Every setting and the reference with empty-space skipping on and/or off (the images agree;
    // only the time differs). The first is the one the reference images come from.
    std::vector<bool> skipping{true};
    // The ray-cast modes unjittered and/or jittered; the reference and half_angle never jitter.
    std::vector<bool> jitter{false};
    // With jitter on: the still refined by each of these step counts (0, the still itself, is
    // always measured), each a point of its own.
    std::vector<int> refinement_steps;
    int repeat = 3;
    // Each point's image written here as PNG (point_image_name), to be looked at or compared
    // elsewhere: what a build without image comparison measures besides the times.
    std::optional<std::filesystem::path> images;
};

// The file a point's image is written to in Sweep::images: every field that tells two points of
// a sweep apart, e.g. "ch2-az10-el45-sbrc-n128-r256-d0.00390625-skip-jitter-k4.png".
std::string point_image_name(const Point& p);

// One setting of a sweep, measured at every sample distance against the references. A new
// dimension of the sweep is a list in Sweep, a field here, and its loop in sweep_settings.
struct SweepSetting {
    scene::Mode mode = scene::Mode::dvr;
    int slices = 0;      // 0 where the mode has none
    int resolution = 0;  // 0 where the mode has no light buffer
    bool skipping = true;
    bool jitter = false;

    // The request with this setting's fields set.
    [[nodiscard]] scene::FrameRequest applied(scene::FrameRequest request) const;
};

// The settings of a sweep in the order they are measured: the modes without slices, then per
// grid point half_angle and the light-buffer modes (which share one build); each with every
// skipping and, where the mode ray-casts, every jitter of the sweep.
std::vector<SweepSetting> sweep_settings(const Sweep& sweep);

// Frames one volume and light cost, so a run can say up front how long it will take.
std::uint64_t frames_per_view(const Sweep& sweep);

// The frame every point of one volume shares (camera, TF, size...).
using FrameFor = std::function<base::Result<scene::FrameRequest>(const volume::Volume&)>;

// Called with every point as it is measured; false stops the sweep after that point.
using PointObserver = std::function<bool(const Point&)>;

// The image a view's points are measured against in their *_truth columns, given the view's frame
// (its light set; the caller renders it as Table::truth says).
using TruthFor = std::function<base::Result<base::ImageRgba8>(const scene::FrameRequest& view)>;

// One volume (already set on the bench's renderer) under one light: the references first, then
// every mode and setting against them and against the truth (`truth`, or where it is empty the
// reference at the finest sample distance), appended to `points`. True when every point was
// measured, false when `observer` stopped the sweep.
base::Result<bool> measure_view(AccuracyBench& bench, const Sweep& sweep, scene::FrameRequest base,
                                const std::string& volume, const LightAngles& light,
                                const PointObserver& observer, std::vector<Point>& points,
                                const TruthFor& truth = {});

}  // namespace penumbra::quality
