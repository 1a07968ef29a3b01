#pragma once

// The measuring half of `penumbra bench accuracy` (DESIGN.md §1 "Accuracy and its cost in time"):
// the table of points, the presets chosen from it, its JSON form (docs/accuracy/README.md), and
// the sweep that renders every point against the `reference`. `penumbra serve` measures a short
// table with the same code at start-up where none exists for the device, so that a frame budget
// is honoured from the same kind of numbers the benchmark writes.

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/camera.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/volume/volume.hpp>

#include <compare>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::app::accuracy {

inline constexpr double infinity = std::numeric_limits<double>::infinity();

// The SSIM window is 11 pixels; a little margin keeps the valid region from being one window.
inline constexpr int min_image_side = 16;

double median(std::vector<double> values);

struct LightAngles {
    double azimuth = 0.0;
    double elevation = 0.0;

    bool operator==(const LightAngles&) const = default;
    auto operator<=>(const LightAngles&) const = default;
};

// ---------------------------------------------------------------------------------------------
// The measured table.

// One mode at one setting, for one volume and light.
struct Point {
    std::string volume;
    LightAngles light;
    scene::Mode mode = scene::Mode::dvr;
    int slices = 0;      // 0 where the mode has no slices
    int resolution = 0;  // 0 where the mode has no light buffer
    double sample_distance = 0.0;
    double frame_ms = 0.0;         // median, light buffer cached
    double light_buffer_ms = 0.0;  // median build; 0 where no separate buffer is built
    // Against the reference of the same sample distance: the error of the shading method alone.
    double rmse = 0.0;
    double psnr = 0.0;  // infinite for an identical image
    double ssim = 1.0;
    // Against the reference of the finest sample distance swept: the error a viewer sees, which
    // also counts coarse sampling. Presets rank by this (the same as above with one distance).
    double rmse_finest = 0.0;
    double psnr_finest = 0.0;
    double ssim_finest = 1.0;
};

struct Table {
    std::string device;      // GL_RENDERER
    std::string vendor;      // GL_VENDOR
    std::string gl_version;  // GL_VERSION
    bool gpu_timers = false;
    int width = 0;
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
    std::vector<Point> points;
};

// A table of this renderer, to be measured with `repeat` timed frames per point.
Table make_table(const render::RendererInfo& info, int repeat, bool phong);

// Records the frame every point of the table shares (size, TF, compositing, camera...).
void describe_frame(Table& table, const scene::FrameRequest& base);

const char* timing_name(const Table& table);

// A setting the presets can choose, over every volume and light measured.
struct SettingKey {
    scene::Mode mode = scene::Mode::dvr;
    int slices = 0;
    int resolution = 0;
    double sample_distance = 0.0;

    auto operator<=>(const SettingKey&) const = default;
};

struct Setting {
    SettingKey key;
    int count = 0;
    double psnr = 0.0;  // mean over the volumes and lights (dB), infinite only for the reference
    double ssim = 0.0;  // mean
    double psnr_finest = 0.0;
    double ssim_finest = 0.0;
    double frame_ms = 0.0;         // mean
    double worst_frame_ms = 0.0;   // the slowest volume and light: what a budget must cover
    double light_buffer_ms = 0.0;  // mean
};

// The points grouped by setting (only those of `volume` where one is named).
std::vector<Setting> aggregate(const std::vector<Point>& points,
                               const std::optional<std::string>& volume = std::nullopt);

// More accurate first: PSNR against the finest reference, then SSIM, then the faster.
bool more_accurate(const Setting& a, const Setting& b);

struct Preset {
    double budget_ms = 0.0;
    std::optional<Setting> setting;  // absent when nothing measured fits
};

// Per budget, the most accurate setting whose slowest frame fits. Only settings measured on every
// volume and light compete, so a mean is never over a subset.
std::vector<Preset> choose_presets(const std::vector<Point>& points,
                                   const std::vector<double>& budgets);

// Six budgets from the fastest setting to the slowest reference, evenly spaced in log time.
std::vector<double> default_budgets(const std::vector<Point>& points);

// The table as docs/accuracy/README.md describes it ("penumbra-accuracy-1").
std::string table_json(const Table& table, const std::vector<Preset>& presets);

// Writes table_json; errors name `option` as where the path came from.
base::Status write_json(const Table& table, const std::vector<Preset>& presets,
                        const std::string& path, const std::string& option = "--json");

// Reads a table written by write_json; errors name `option` as where the path came from.
base::Result<Table> read_table(const std::string& path, const std::string& option = "--from");

// ---------------------------------------------------------------------------------------------
// Measuring.

struct Timed {
    base::ImageRgba8 image;
    double frame_ms = 0.0;
};

struct Errors {
    double rmse = 0.0;
    double psnr = 0.0;
    double ssim = 1.0;
};

// RMSE and PSNR over RGB, SSIM on luma.
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

    // The light-buffer pass alone, rebuilt every frame by nudging the light to and fro, on tiny
    // frames (the buffer does not depend on the image size).
    base::Result<double> light_buffer_build(scene::FrameRequest request);

private:
    base::Result<render::Frame> render(const scene::FrameRequest& request);

    render::FrameRenderer& renderer_;
    int repeat_;
    std::uint64_t nudges_ = 0;  // distinct lights used by build measurements so far
    bool gpu_timers_;
    std::uint64_t frames_ = 0;
};

// What to sweep.
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
    int repeat = 3;
};

// Frames one volume and light cost, so a run can say up front how long it will take.
std::uint64_t frames_per_view(const Sweep& sweep);

// Called with every point as it is measured; false stops the sweep after that point.
using PointObserver = std::function<bool(const Point&)>;

// One volume (already set on the bench's renderer) under one light: the references first, then
// every mode and setting against them, appended to `points`. True when every point was measured,
// false when `observer` stopped the sweep.
base::Result<bool> measure_view(AccuracyBench& bench, const Sweep& sweep, scene::FrameRequest base,
                                const std::string& volume, const LightAngles& light,
                                const PointObserver& observer, std::vector<Point>& points);

// ---------------------------------------------------------------------------------------------
// The short table `penumbra serve` measures at start-up where no table exists for the device.

struct StartupOptions {
    int side = 256;  // square frames
    // Checked between points: start-up stays bounded on a slow device, which then serves with
    // the points measured so far.
    double time_limit_s = 60.0;
    Sweep sweep;  // volumes is ignored: the volume is given
};

// phong; half_angle n 64, 128 at R 128; sbrc and sbrc_cone at n 64, 128, 256 x R 128, 256; the
// reference; light 10,45, sample distance 1/256, 3 timed frames: about 100 frames, under a minute
// at 256² on llvmpipe.
StartupOptions startup_options();

struct StartupTable {
    Table table;
    bool complete = true;  // false: stopped at the time limit
    double seconds = 0.0;
};

// Measures the sweep of `options` on `volume` with the frame defaults of `penumbra render`.
base::Result<StartupTable> measure_startup_table(render::FrameRenderer& renderer,
                                                 std::shared_ptr<const volume::Volume> volume,
                                                 const StartupOptions& options);

}  // namespace penumbra::app::accuracy
