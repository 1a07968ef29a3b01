#pragma once

// --truth-cache, which `bench accuracy` and `bench truth` share: where the converged truths
// (bench/truth.hpp) are kept between runs.

#include <penumbra/base/data_dir.hpp>
#include <penumbra/cli/options.hpp>

#include <filesystem>
#include <optional>
#include <string>

namespace penumbra::app {

inline void add_truth_cache_option(cli::po::options_description& options) {
    options.add_options()("truth-cache", cli::po::value<std::string>()->value_name("DIR|none"),
                          "where the converged truths are kept between runs, one per volume, "
                          "view, light, transfer function and size (default: the user's cache "
                          "folder's truth/, ~/.cache/penumbra/truth; none: this run only)");
}

// The folder --truth-cache names; by default the user's cache folder's truth/ where there is one;
// none for "none".
inline std::optional<std::filesystem::path> truth_folder(const cli::po::variables_map& a) {
    if (a.count("truth-cache") == 0) {
        const auto cache = base::user_cache_dir();
        return cache ? std::optional(*cache / "truth") : std::nullopt;
    }
    const std::string folder = a["truth-cache"].as<std::string>();
    return folder == "none" ? std::nullopt : std::optional<std::filesystem::path>(folder);
}

}  // namespace penumbra::app
