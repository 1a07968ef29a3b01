#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/cli/options.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/volume/volume.hpp>

#include <string>
#include <utility>
#include <vector>

namespace penumbra::cli {

// What a command's frame is for, which picks the frame its options start from: a measurement's
// (the benchmarks: each frame on its own, samples at the middle of each step) or a still's
// (`penumbra render`: jittered samples, which the command's refinement averages; `--no-jitter`
// turns them off).
enum class FramePurpose { measurement, still };

// The options that describe a frame, shared by every command that renders, less those a
// benchmark sweeps itself (`swept`).
po::options_description frame_options(const std::vector<std::string>& swept = {},
                                      FramePurpose purpose = FramePurpose::measurement);

// Builds a frame request from those options; defaults give a useful view of a head.
base::Result<scene::FrameRequest> frame_request_from(
        const po::variables_map& options, const volume::Volume& volume,
        FramePurpose purpose = FramePurpose::measurement);

// The frame those options give when none is given: the defaults of `penumbra render` and
// `bench accuracy`, from which the committed accuracy tables were measured.
base::Result<scene::FrameRequest> default_frame_request(const volume::Volume& volume);

// A benchmark's options it sweeps itself, each with what to give instead.
using SweptOptions = std::vector<std::pair<std::string, std::string>>;

// The names of `swept`.
std::vector<std::string> names_of(const SweptOptions& swept);

// A usage error for a swept option says that `benchmark` sweeps it and what to give instead.
base::Error explain_swept(base::Error error, const SweptOptions& swept, const char* benchmark);

}  // namespace penumbra::cli
