#pragma once

// `penumbra bench modes` as a whole: each mode's frame time over slices x light-buffer
// resolution, the light buffer cached against rebuilt, the two builders, the two light lookups,
// the ratios that matter, and the optimisation table (optimisation_bench.hpp). Printed as it is
// measured; the points of the sweeps optionally written as CSV rows.

#include <penumbra/base/result.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/volume/volume.hpp>

#include <cstdio>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace penumbra::bench {

struct ModesBenchConfig {
    std::string volume;                // the volume the sweeps run on
    std::vector<std::string> volumes;  // the optimisation table's volumes
    std::vector<scene::Mode> modes;
    std::vector<int> slices;
    std::vector<int> resolutions;
    int repeat = 5;  // timed frames per point after one warm-up
    render::GradientSource gradients = render::GradientSource::automatic;
    int brick_voxels = 0;     // 0: the renderer's default
    bool debug_gl = false;    // GL debug output to the log
    bool only_table = false;  // the optimisation table without the sweeps
    // A label map drawn inside the sweeps' volume in a table of its own (measure_labels); empty:
    // no label table.
    std::string labels;
    // The sweeps' rows, and the file's name for the report; null: none written.
    std::ostream* csv = nullptr;
    std::string csv_path;
    // The frame each point starts from on a loaded volume (its mode, slices and light-buffer
    // resolution are swept).
    std::function<base::Result<scene::FrameRequest>(const volume::Volume&)> frame_for;
};

base::Status bench_modes(const ModesBenchConfig& config, std::FILE* out);

}  // namespace penumbra::bench
