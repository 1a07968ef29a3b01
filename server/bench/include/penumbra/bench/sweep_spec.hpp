#pragma once

// An accuracy sweep as a person asks for it: its lists as typed ("10,45;100,20", "1/256,1/512"),
// the defaults of the kind of device it runs on, and a named case; make_sweep turns them into the
// quality::Sweep that is measured (penumbra/quality/sweep.hpp).

#include <penumbra/base/result.hpp>
#include <penumbra/quality/sweep.hpp>
#include <penumbra/quality/table.hpp>
#include <penumbra/scene/mode.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::bench {

// A named case of `bench accuracy --case`: a transfer function and the volumes it suits. How
// much the light buffer saves depends on it: where camera and shadow rays stop at an opaque
// surface the reference costs little more than a light-buffer mode; where they cross translucent
// tissue, a shadow ray per sample costs a march per sample.
struct AccuracyCase {
    const char* name;
    const char* transfer_function;  // a preset
    const char* volumes;            // files, comma-separated; nullptr: the device's defaults
    bool head_ct;                   // the volume is the head CT (scripts/demo-data.sh)
    const char* what;
};

// mri_skin (the opaque skin on the default MRI heads), mri_brain (ch2bet, the brain alone,
// translucent grey and white matter), ct_bone (the head CT's skull) and ct_soft_tissue (the head
// CT's translucent soft tissue).
const std::vector<AccuracyCase>& accuracy_cases();

// The case of that name, if there is one.
const AccuracyCase* find_accuracy_case(std::string_view name);

// The lists' texts read. The errors say what is expected; where they are is the caller's to say.
// Whole numbers from 1 to 65536, each once, in the order given (light slices, resolutions).
base::Result<std::vector<int>> parse_counts(std::string_view text);
// Sample distances in (0, 1], each may be a fraction "1/N"; finest first, each once.
base::Result<std::vector<double>> parse_distances(std::string_view text);
// Directional lights in degrees: "AZIMUTH,ELEVATION;AZIMUTH,ELEVATION...".
base::Result<std::vector<quality::LightAngles>> parse_lights(std::string_view text);
// "on", "off", "on,off" or "off,on": each once, in the order given.
base::Result<std::vector<bool>> parse_switches(std::string_view text);
// Refinement step counts in 0..scene::kMaxRefinementSteps, sorted, each once; 0 (the still, which
// is always measured) left out.
base::Result<std::vector<int>> parse_refinement_steps(std::string_view text);

// A sweep's defaults, in the lists' text form (help texts show them as they are). A GPU's, and
// lighter ones for a software rasteriser (no working timer queries, llvmpipe here), where the full
// sweep would take hours; the lighter sweep takes minutes at 256².
struct SweepDefaults {
    const char* volumes;
    const char* lights;
    const char* slices;
    const char* resolutions;
    const char* sample_distances;
    int side;  // the images' width and height
    int repeat;
};

// The defaults of a device whose GPU timer queries work, or of one whose do not.
const SweepDefaults& sweep_defaults(bool gpu_timers);

// What was asked for; each list not given takes the device's default.
struct SweepSpec {
    std::optional<std::vector<std::string>> volumes;  // none: the case's, else the defaults
    std::optional<std::vector<quality::LightAngles>> lights;
    std::optional<std::vector<scene::Mode>> modes;  // none: every mode; never the reference
    std::optional<std::vector<int>> slices;
    std::optional<std::vector<int>> resolutions;
    std::optional<std::vector<double>> distances;
    std::optional<int> repeat;  // 1..1000
    std::vector<bool> skipping{true};
    std::vector<bool> jitter{false};
    std::vector<int> refinement_steps;  // needs jitter on
    const AccuracyCase* accuracy_case = nullptr;
    // The head CT where scripts/demo-data.sh converted it: the head-CT case's volume, and one of
    // the defaults without a case.
    std::optional<std::filesystem::path> head_ct;
};

// The volumes a sweep measures: --volumes, else the case's, else the defaults with the head CT
// where it was made. Errors: a head-CT case without the head CT (at --case).
base::Result<std::vector<std::string>> sweep_volumes(const SweepSpec& spec,
                                                     const SweepDefaults& defaults);

// The sweep to measure; errors name the option at fault (--repeat, --refinement, --case).
base::Result<quality::Sweep> make_sweep(const SweepSpec& spec, const SweepDefaults& defaults);

// The case of that name; else an error listing the cases, at --case.
base::Result<const AccuracyCase*> accuracy_case_named(std::string_view name);

}  // namespace penumbra::bench
