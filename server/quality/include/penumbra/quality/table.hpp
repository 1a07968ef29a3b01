#pragma once

// The accuracy table (DESIGN.md §1 "Accuracy and its cost in time"): what each rendering mode at
// each setting cost per frame and how close it came to the reference, as `penumbra bench accuracy`
// measures it and `penumbra serve` uses it to honour a frame budget. One model, one rule:
//
// A setting competes only where it was measured on every volume and light of the table, so that
// its mean is never over an easier subset. It ranks by its mean PSNR against the table's truth
// (the error a viewer sees, coarse sampling included: the converged reference of `bench
// accuracy`, or, in a table measured without one, the reference at the finest sample distance
// measured), then by its mean SSIM against that truth, then by the faster. It fits a budget when
// its slowest frame, scaled by pixel count to the requested image size, does. PSNR is infinite only
// for an image identical to the reference; it is kept infinite (never capped at an arbitrary number
// of decibels), so the exact setting ranks above every approximate one and SSIM, not a made-up
// figure, decides between two exact ones. The slowest frame, not the mean, must fit because a
// budget promises every frame, whichever volume and light the viewer has.
//
// Empty-space skipping is part of a setting (it changes only the time) and is applied with it.
// Jittered settings and refined images (refinement steps after a jittered still) are plotted but
// never chosen: jitter moves the samples without adding any, so a setting's time holds jittered
// or not and whether to jitter (and so to refine) stays the viewer's choice; and a budget covers
// each frame, while the steps that refine a still run after it, at the lowest priority.

#include <penumbra/scene/camera.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <compare>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::quality {

inline constexpr double infinity = std::numeric_limits<double>::infinity();

struct LightAngles {
    double azimuth = 0.0;
    double elevation = 0.0;

    bool operator==(const LightAngles&) const = default;
    auto operator<=>(const LightAngles&) const = default;
};

// One mode at one setting, for one volume and light.
struct Point {
    std::string volume;
    LightAngles light;
    scene::Mode mode = scene::Mode::dvr;
    int slices = 0;      // 0 where the mode has no slices
    int resolution = 0;  // 0 where the mode has no light buffer
    double sample_distance = 0.0;
    bool empty_space_skipping = true;
    bool jitter = false;       // ray-cast modes only; never the reference
    int refinement_steps = 0;  // > 0: the jittered still after this many refinement steps
    // Median, light buffer cached; for a refined image the median of its steps' frames (the
    // image is on screen after refinement_steps + 1 frames).
    double frame_ms = 0.0;
    double light_buffer_ms = 0.0;  // median build; 0 where no separate buffer is built
    // Against the reference of the same sample distance: the error of the shading method alone.
    double rmse = 0.0;
    double psnr = 0.0;  // infinite for an identical image
    double ssim = 1.0;
    // Against the table's truth (Table::truth): the error a viewer sees, which also counts the
    // sample distance's own error. Settings rank by this.
    double rmse_truth = 0.0;
    double psnr_truth = 0.0;
    double ssim_truth = 1.0;
};

// How a table's truth was rendered: the `reference` mode (shadow rays) at this sample distance,
// jittered, the mean of this many frames (a still and its refinement steps): an estimate of the
// continuous volume rendering integral (bench/truth.hpp says how the numbers were chosen).
struct TruthMethod {
    double sample_distance = 0.0;
    int frames = 1;

    bool operator==(const TruthMethod&) const = default;
};

struct Table {
    std::string device;      // GL_RENDERER
    std::string vendor;      // GL_VENDOR
    std::string gl_version;  // GL_VERSION
    bool gpu_timers = false;
    int width = 0;  // the image size every point was measured at
    int height = 0;
    int repeat = 0;
    std::string transfer_function;
    std::string compositing;
    std::string stage;
    std::string builder;
    std::string light_lookup;  // how the sbrc modes read the light buffer
    int slab_samples = 0;      // as requested: 0 = one per voxel
    bool phong = true;
    scene::Camera camera;
    // What the *_truth columns compare with; none: the reference at the finest sample distance
    // swept (the start-up table, and tables measured before the converged truth existed).
    std::optional<TruthMethod> truth;
    std::vector<Point> points;
};

// "gpu" (timer queries) or "wall" (wall clock).
const char* timing_name(const Table& table);

// What a setting is: the fields a chosen setting changes in a request, and the refinement steps
// that its image holds.
struct SettingKey {
    scene::Mode mode = scene::Mode::dvr;
    int slices = 0;
    int resolution = 0;
    double sample_distance = 0.0;
    bool empty_space_skipping = true;
    bool jitter = false;
    int refinement_steps = 0;

    // Skipping on, jitter off, no refinement: the request's defaults.
    [[nodiscard]] bool plain() const;

    auto operator<=>(const SettingKey&) const = default;
};

// A setting over the volumes and lights it was measured on.
struct Setting {
    SettingKey key;
    int count = 0;
    double psnr = 0.0;  // mean over the volumes and lights (dB), infinite only for the reference
    double ssim = 0.0;  // mean
    double psnr_truth = 0.0;
    double ssim_truth = 0.0;
    double frame_ms = 0.0;         // mean
    double worst_frame_ms = 0.0;   // the slowest volume and light: what a budget must cover
    double light_buffer_ms = 0.0;  // mean
};

// The points grouped by setting (only those of `volume` where one is named).
std::vector<Setting> aggregate(const std::vector<Point>& points,
                               const std::optional<std::string>& volume = std::nullopt);

// The rule's order: the higher mean PSNR against the truth, then the higher mean SSIM against it,
// then the faster slowest frame.
bool more_accurate(const Setting& a, const Setting& b);

// The settings a budget can choose (unjittered, so unrefined) measured on every volume and light
// of `points`, most accurate first.
std::vector<Setting> candidates(const std::vector<Point>& points);

struct Choice {
    Setting setting;
    double estimated_ms = 0.0;  // the slowest frame scaled to the requested image size
    bool fits = true;           // false: nothing fits, this is the fastest setting measured

    // "budget 50 ms: sbrc n=32 R=64 dt=1/256, about 40 ms, 24.0 dB" (the frame header's text).
    [[nodiscard]] std::string describe(double budget_ms) const;
};

// The most accurate candidate whose slowest frame, scaled by pixel count from the table's size to
// width x height, fits `budget_ms`; when none fits, the fastest candidate, marked as not fitting.
// Nothing when the table has no candidate.
std::optional<Choice> choose(const Table& table, double budget_ms, int width, int height);

// The request with the chosen setting applied (mode, slices, resolution, sample distance,
// skipping); the slices and resolution only where the setting has them. The request's jitter
// stays as it is.
scene::FrameRequest apply(scene::FrameRequest request, const SettingKey& setting);

struct Preset {
    double budget_ms = 0.0;
    std::optional<Setting> setting;  // absent when nothing measured fits
};

// `choose` per budget at the table's own image size.
std::vector<Preset> choose_presets(const Table& table, const std::vector<double>& budgets);

// Six budgets from the fastest setting to the slowest reference, evenly spaced in log time.
std::vector<double> default_budgets(const std::vector<Point>& points);

}  // namespace penumbra::quality
