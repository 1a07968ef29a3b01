#pragma once

// Where `penumbra serve` gets its accuracy table (DESIGN.md §1): a file named on the command
// line, else the table committed for this kind of device (docs/accuracy, installed under
// share/penumbra/accuracy), else one measured at start-up and cached per GL_RENDERER, so that a
// frame budget is honoured from the same kind of numbers `bench accuracy` writes.

#include <penumbra/base/data_dir.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/quality/sweep.hpp>
#include <penumbra/quality/table.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/volume/volume.hpp>

#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::quality {

// ---------------------------------------------------------------------------------------------
// The short table measured at start-up.

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

// Measures the sweep of `options` on `volume`, from `frame` (the camera, transfer function and
// lighting of `penumbra render`'s defaults; its size is replaced by options.side).
base::Result<StartupTable> measure_startup_table(
        render::FrameRenderer& renderer, const std::shared_ptr<const volume::Volume>& volume,
        scene::FrameRequest frame, const StartupOptions& options);

// ---------------------------------------------------------------------------------------------
// The serve policy.

enum class Measure {
    never,          // --no-quality-measure, or a table given on the command line
    where_missing,  // no committed and no cached table for this device
    always,         // --quality-measure
};

// The tables of one kind of device.
struct TablePaths {
    // share/penumbra/accuracy/{gpu,llvmpipe}.json: measured by `bench accuracy` and committed.
    std::filesystem::path committed;
    // In the user's cache folder (base::user_cache_dir), one file per GL_RENDERER; nothing
    // without one.
    std::optional<std::filesystem::path> cache;
};

// `cache_dir`: the user's cache folder, or where a test keeps its files.
TablePaths table_paths(
        const render::RendererInfo& info,
        const std::optional<std::filesystem::path>& cache_dir = base::user_cache_dir());

// Whether the start-up table is to be measured.
bool should_measure(Measure measure, const TablePaths& paths);

// The volume the start-up table is measured on: ch2 (the default volume everywhere) where it is
// offered, else the first one; nothing when none is.
std::optional<std::string> startup_volume(const std::vector<std::string>& offered);

// What the render thread measured before taking work (an error where it tried and failed).
struct StartupMeasurement {
    std::optional<StartupTable> table;
    std::string volume;
    std::optional<base::Error> error;
};

// The volumes a server offers, as the start-up measurement sees them.
struct OfferedVolumes {
    // The ids offered; asked only when a measurement is due (a server may still be scanning its
    // data folder when the renderer starts: the function waits for what it needs).
    std::function<std::vector<std::string>()> ids;
    std::function<base::Result<std::shared_ptr<const volume::Volume>>(const std::string&)> acquire;
};

// Called on the render thread with the renderer that will serve, before it takes work (its GL
// context is current on that thread only, and a second context would cost another one): measures
// the start-up table on startup_volume(volumes.ids) where `measure` and the tables on disk say
// so, saying so on `out` first; `frame_for` gives the camera, transfer function and lighting of
// `penumbra render`'s defaults, which the committed tables were measured with. Nothing measured:
// no table and no error.
StartupMeasurement measure_at_startup(render::FrameRenderer& renderer, Measure measure,
                                      const OfferedVolumes& volumes, const FrameFor& frame_for,
                                      std::FILE* out);

struct ServeTable {
    std::shared_ptr<const Table> table;  // null: frame budgets are ignored
    std::vector<std::string> notes;      // what was done, one line each, for the log
};

// In order: `given` (a file named on the command line: an error where it cannot be read), the
// start-up measurement (then cached where there is a cache), the committed table (an error where
// it exists and is not a table), the cached one (ignored where it is not a table: a cache is ours
// to replace, and serving without budgets beats not serving).
base::Result<ServeTable> serve_table(const std::optional<std::filesystem::path>& given,
                                     const StartupMeasurement& measured, const TablePaths& paths);

}  // namespace penumbra::quality
