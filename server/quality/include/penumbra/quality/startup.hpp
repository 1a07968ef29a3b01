#pragma once

// Where `penumbra serve` gets its accuracy table (DESIGN.md §1): a file named on the command
// line, else the table committed for this kind of device (docs/accuracy, installed under
// share/penumbra/accuracy), else one measured at start-up and cached per GL_RENDERER, so that a
// frame budget is honoured from the same kind of numbers `bench accuracy` writes.

#include <penumbra/base/result.hpp>
#include <penumbra/quality/sweep.hpp>
#include <penumbra/quality/table.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/volume/volume.hpp>

#include <filesystem>
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
base::Result<StartupTable> measure_startup_table(render::FrameRenderer& renderer,
                                                 std::shared_ptr<const volume::Volume> volume,
                                                 scene::FrameRequest frame,
                                                 const StartupOptions& options);

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
    // $XDG_CACHE_HOME/penumbra, else ~/.cache/penumbra, one file per GL_RENDERER; nothing
    // without either variable.
    std::optional<std::filesystem::path> cache;
};

// `xdg_cache_home` and `home` are the environment's values (nullptr where unset).
TablePaths table_paths(const render::RendererInfo& info, const char* xdg_cache_home,
                       const char* home);

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
