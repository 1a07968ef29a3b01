#pragma once

#include <penumbra/cli/options.hpp>
#include <penumbra/quality/sweep_spec.hpp>

namespace penumbra::app {

// The benchmarks' sweep lists as options, each read by quality's parser of it.
using Counts = cli::ListOf<&quality::parse_counts>;  // slices, resolutions: 1..65536, each once
using Distances = cli::ListOf<&quality::parse_distances>;
using Lights = cli::ListOf<&quality::parse_lights>;
using Switches = cli::ListOf<&quality::parse_switches>;
using Steps = cli::ListOf<&quality::parse_refinement_steps>;

}  // namespace penumbra::app
