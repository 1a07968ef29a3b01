#include "arguments.hpp"
#include "commands.hpp"

#include <penumbra/net/load.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

namespace penumbra::app {
namespace {

void print_load_usage() {
    std::puts(
            "usage: penumbra load --port P [options]\n\n"
            "N simulated clients on one server, each orbiting the camera and waiting for each\n"
            "frame before asking for the next. Reports the latency from request sent to frame\n"
            "received (p50/p95/p99), its server-side split, frames/s, bytes/s and errors.\n\n"
            "  --host H          (default 127.0.0.1)\n"
            "  --port P          the server's port (required)\n"
            "  --clients N       simulated clients (default 4, at most 256)\n"
            "  --seconds T       how long to run (default 10, at most 3600)\n"
            "  --volume ID       volume id from list_volumes (default ch2.nii.gz)\n"
            "  --mode MODE       (default sbrc)\n"
            "  --size S          frames of S x S pixels (default 512)\n"
            "  --encoding E      jpeg | png (default jpeg)\n"
            "  --interactive     request interactive-quality frames\n"
            "  --refine N        jittered frames, each still refined N times at the lowest\n"
            "                    priority (progressive stills; counted apart)\n"
            "  --token-file F    the access token a server or proxy asks for\n\n"
            "The WebSocket URL names the volume (/ws?volume=ID), as a cluster's proxy routes\n"
            "by it (proto/README.md).");
}

// The load run the options describe; a message for stderr where they are wrong.
base::Result<net::LoadConfig> load_config(const Arguments& a) {
    net::LoadConfig config;
    config.host = a.get("host").value_or(config.host);
    config.volume = a.get("volume").value_or(config.volume);
    config.mode = a.get("mode").value_or(config.mode);
    config.encoding = a.get("encoding").value_or(config.encoding);
    config.interactive = a.has("interactive");
    const auto refine = a.integer("refine", 0);
    if (!refine || *refine < 0 || *refine > scene::kMaxRefinementSteps) {
        return base::make_error(
                "invalid_argument",
                "--refine takes 0.." + std::to_string(scene::kMaxRefinementSteps) + " steps");
    }
    config.refine = *refine;
    if (const auto token_file = a.get("token-file")) {
        std::ifstream in(*token_file);
        if (!in || !std::getline(in, config.token) || config.token.empty()) {
            return base::make_error("invalid_argument",
                                    "--token-file: cannot read a token from '" + *token_file + "'");
        }
    }
    auto port = a.integer("port", 0);
    auto clients = a.integer("clients", config.clients);
    auto size = a.integer("size", config.size);
    auto seconds = a.number("seconds", config.seconds);
    if (!port || !clients || !size || !seconds || *port < 1 || *port > 65535 || *clients < 1 ||
        *clients > 256 || *size < 16 || *size > 8192 || *seconds <= 0.0 || *seconds > 3600.0) {
        return base::make_error("invalid_argument",
                                "--port is required; --clients 1..256, --size 16..8192, "
                                "--seconds (0, 3600]");
    }
    config.port = static_cast<unsigned short>(*port);
    config.clients = *clients;
    config.size = *size;
    config.seconds = *seconds;
    return config;
}

}  // namespace

int run_load(const std::vector<std::string>& args) {
    auto parsed = Arguments::parse(args,
                                   {"host", "port", "clients", "seconds", "volume", "mode", "size",
                                    "encoding", "token-file", "refine"},
                                   {"help", "interactive"});
    if (!parsed) {
        std::fprintf(stderr, "penumbra load: %s (see --help)\n",
                     parsed.error().to_string().c_str());
        return 2;
    }
    if (parsed->has("help")) {
        print_load_usage();
        return 0;
    }
    const auto config = load_config(*parsed);
    if (!config) {
        std::fprintf(stderr, "penumbra load: %s\n", config.error().message.c_str());
        return 2;
    }
    const net::LoadReport report = net::run_load(*config);
    net::print_load_report(*config, report, stdout);
    return report.ok() ? 0 : 1;
}

}  // namespace penumbra::app
