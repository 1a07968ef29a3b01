#pragma once

#include <penumbra/base/data_dir.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

namespace penumbra::app {

// Each subcommand takes the arguments after its name and returns the process exit status.
int run_render(const std::vector<std::string>& args);
int run_info(const std::vector<std::string>& args);
int run_serve(const std::vector<std::string>& args);
int run_load(const std::vector<std::string>& args);
// `bench modes`, `bench accuracy` and `bench refine`.
int run_bench(const std::vector<std::string>& args);
int run_bench_accuracy(const std::vector<std::string>& args);
int run_bench_refine(const std::vector<std::string>& args);

// The volume every command uses when none is given: the Colin27 MRI head that Debian's
// mricron-data package installs.
inline constexpr const char* mricron_templates = "/usr/share/mricron/templates";
inline constexpr const char* default_volume_path = "/usr/share/mricron/templates/ch2.nii.gz";

// The demo data folder that scripts/demo-data.sh makes in the user's cache: the CT it converts,
// beside links to the MRI heads. It may not exist.
inline std::optional<std::filesystem::path> demo_data_dir() {
    if (const auto cache = base::user_cache_dir()) {
        return *cache / "volumes";
    }
    return std::nullopt;
}

// InVesalius' head CT (Debian's invesalius-examples) where scripts/demo-data.sh converted it into
// the demo data folder; nothing before that ran.
inline std::optional<std::filesystem::path> demo_ct_path() {
    std::error_code ec;
    if (const auto folder = demo_data_dir()) {
        const std::filesystem::path path = *folder / "cranium_ct.nrrd";
        if (std::filesystem::is_regular_file(path, ec)) {
            return path;
        }
    }
    return std::nullopt;
}

}  // namespace penumbra::app
