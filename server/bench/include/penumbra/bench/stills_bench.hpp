#pragma once

// `penumbra bench stills`: what a user sees of each mode, against the converged truth. For every
// case (a volume and a transfer function) and mode, from the view `penumbra render` gives by
// default, four frames: the still as it was before stills were jittered (`unjittered`), the frame
// shown while the user drags (`interactive`: scene::interactive_request, half the size and light
// buffer and twice the step, stretched back to the view's size as the browser shows it), the
// first jittered still, and the still refined as a session refines it (`converged`: until a step
// changes the image by the threshold or less, or the step limit). Each with PSNR and SSIM against
// the truth and its time; the converged still's is the still's plus every step's, what a user
// waits for it.

#include <penumbra/base/enum_names.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/bench/truth.hpp>
#include <penumbra/quality/sweep.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/frame_request.hpp>
#include <penumbra/scene/mode.hpp>
#include <penumbra/volume/volume.hpp>

#include <array>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::bench {

// The frames measured of every mode, in the order they are rendered and printed.
// unjittered_same_time: the unjittered still given the converged still's time, spent as before
// stills converged could spend it: on a finer step (halved while the frame still fits that time).
enum class StillFrame { unjittered, interactive, first, converged, unjittered_same_time };

inline constexpr std::array<base::EnumName<StillFrame>, 5> kStillFrames{{
        {StillFrame::unjittered, "unjittered"},
        {StillFrame::interactive, "interactive"},
        {StillFrame::first, "first"},
        {StillFrame::converged, "converged"},
        {StillFrame::unjittered_same_time, "unjittered_same_time"},
}};
static_assert(base::names_each_value(kStillFrames));

constexpr std::span<const base::EnumName<StillFrame>> names_of(StillFrame) {
    return kStillFrames;
}

// One volume under one transfer function.
struct StillsCase {
    std::string name;    // the accuracy case's ("ct_bone")
    std::string volume;  // its file
};

struct StillsConfig {
    std::vector<StillsCase> cases;
    std::vector<scene::Mode> modes;
    // The view on a volume, with the case's transfer function: the frame options over
    // `penumbra render`'s defaults.
    std::function<base::Result<scene::FrameRequest>(const volume::Volume&, const StillsCase&)>
            frame_for;
    int max_steps = scene::kDefaultRefinementSteps;
    double threshold = scene::kDefaultRefinementThreshold;
    int repeat = 1;  // timed frames of each still and interactive frame after 1 warm-up
    // Where set, the images are written there: CASE_truth.png and CASE_MODE_FRAME.png.
    std::optional<std::filesystem::path> images;
};

struct StillsRow {
    std::string case_name;
    scene::Mode mode = scene::Mode::sbrc;
    StillFrame frame = StillFrame::first;
    quality::Errors errors;  // against the truth
    double ms = 0.0;
    int steps = 0;                 // refinement steps (converged only)
    double sample_distance = 0.0;  // the frame's step (the still's, or the refinement steps')
};

// What the default still must reach, by case: the targets for sbrc, the default mode.
struct StillsTarget {
    std::string_view case_name;  // "" for every case
    StillFrame frame;
    double psnr;  // at least, dB
};

inline constexpr std::array<StillsTarget, 4> kStillsTargets{{
        {"ct_bone", StillFrame::converged, 42.0},
        {"mri_skin", StillFrame::converged, 46.0},
        {"", StillFrame::first, 40.0},
        {"", StillFrame::interactive, 36.0},
}};

// Measures every case and mode on `renderer`, printing each row as it comes and, at the end, each
// target of the default mode met or missed with its margin.
base::Result<std::vector<StillsRow>> bench_stills(render::FrameRenderer& renderer,
                                                  const StillsConfig& config, TruthCache& cache,
                                                  std::FILE* out);

// One line per row: case,mode,frame,psnr,ssim,rmse,ms,steps,sample_distance.
base::Status write_stills_csv(const std::vector<StillsRow>& rows,
                              const std::filesystem::path& path);

}  // namespace penumbra::bench
