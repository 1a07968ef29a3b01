#pragma once

#include <string>
#include <vector>

namespace penumbra::app {

// Each subcommand takes the arguments after its name and returns the process exit status.
int run_render(const std::vector<std::string>& args);
int run_info(const std::vector<std::string>& args);
int run_serve(const std::vector<std::string>& args);
int run_load(const std::vector<std::string>& args);
// `bench modes`, `bench accuracy`, `bench encode`, `bench refine`, `bench stills` and
// `bench truth`.
int run_bench(const std::vector<std::string>& args);
int run_bench_accuracy(const std::vector<std::string>& args);
int run_bench_encode(const std::vector<std::string>& args);
int run_bench_refine(const std::vector<std::string>& args);
int run_bench_stills(const std::vector<std::string>& args);
int run_bench_truth(const std::vector<std::string>& args);

// The volume every command uses when none is given: the Colin27 MRI head that Debian's
// mricron-data package installs.
inline constexpr const char* mricron_templates = "/usr/share/mricron/templates";
inline constexpr const char* default_volume_path = "/usr/share/mricron/templates/ch2.nii.gz";

}  // namespace penumbra::app
