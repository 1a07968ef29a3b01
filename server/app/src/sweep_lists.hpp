#pragma once

#include <penumbra/bench/sweep_spec.hpp>
#include <penumbra/cli/options.hpp>

namespace penumbra::app {

// The benchmarks' sweep lists as options, each read by bench's parser of it.
using Counts = cli::ListOf<&bench::parse_counts>;  // slices, resolutions: 1..65536, each once
using Distances = cli::ListOf<&bench::parse_distances>;
using Lights = cli::ListOf<&bench::parse_lights>;
using Switches = cli::ListOf<&bench::parse_switches>;
using Steps = cli::ListOf<&bench::parse_refinement_steps>;

}  // namespace penumbra::app
