#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/cli/options.hpp>
#include <penumbra/net/load.hpp>

namespace penumbra::app {

// `penumbra load`'s options: the run they describe, and the values read as typed before they are
// checked together.
struct LoadOptions {
    net::LoadConfig config;
    int port = 0;
    cli::Number seconds{config.seconds};
};

// The options, stored into `o`.
cli::po::options_description load_options(LoadOptions& o);

// What the options leave to be read or checked together (--token-file is read as `serve` reads
// its secrets); a message for stderr where they are wrong.
base::Status finish_load_options(const cli::po::variables_map& a, LoadOptions& o);

}  // namespace penumbra::app
