#include "commands.hpp"
#include "load_options.hpp"

#include <penumbra/base/secret.hpp>
#include <penumbra/cli/options.hpp>
#include <penumbra/net/load.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace penumbra::app {

using namespace cli;

po::options_description load_options(LoadOptions& o) {
    net::LoadConfig& c = o.config;
    po::options_description options = option_group("options");
    options.add_options()("help", "this text")(
            "host", po::value(&c.host)->value_name("H")->default_value(c.host), "server address")(
            "port", po::value(&o.port)->value_name("P"), "the server's port (required)")(
            "clients", po::value(&c.clients)->value_name("N")->default_value(c.clients),
            "simulated clients (at most 256)")(
            "seconds", po::value(&o.seconds)->value_name("T")->default_value(o.seconds),
            "how long to run (at most 3600)")(
            "volume", po::value(&c.volume)->value_name("ID")->default_value(c.volume),
            "volume id from list_volumes")(
            "mode", po::value(&c.mode)->value_name("MODE")->default_value(c.mode),
            "rendering mode")("size", po::value(&c.size)->value_name("S")->default_value(c.size),
                              "frames of S x S pixels")(
            "encoding",
            po::value(&c.encoding)
                    ->value_name(scene::name_list<scene::FrameFormat>("|"))
                    ->default_value(c.encoding),
            "frame encoding")("interactive", "request interactive-quality frames")(
            "refine", po::value(&c.refine)->value_name("N")->default_value(c.refine),
            "jittered frames, each still refined N times at the lowest priority (progressive "
            "stills; counted apart); 0: stills not refined")(
            "token-file", po::value<std::string>()->value_name("F"),
            "the access token a server or proxy asks for");
    return options;
}

base::Status finish_load_options(const po::variables_map& a, LoadOptions& o) {
    net::LoadConfig& config = o.config;
    config.interactive = a.count("interactive") != 0;
    if (config.refine < 0 || config.refine > scene::kMaxRefinementSteps) {
        return base::make_error(
                base::ErrorCode::invalid_argument,
                "--refine takes 0.." + std::to_string(scene::kMaxRefinementSteps) + " steps");
    }
    if (a.count("token-file") != 0) {
        // Read as `serve` reads its secrets: the line end an editor or `echo` leaves (LF or CRLF)
        // is no part of it. A file is named, so the environment variable is not consulted.
        const std::filesystem::path file = a["token-file"].as<std::string>();
        auto token = base::read_secret(file, "PENUMBRA_ACCESS_TOKEN", "--token-file");
        if (!token) {
            return base::make_error(
                    base::ErrorCode::invalid_argument,
                    "--token-file: cannot read a token from '" + file.string() + "'");
        }
        config.token = *token;
    }
    if (!scene::parse_name<scene::FrameFormat>(config.encoding)) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "--encoding takes " + scene::choices<scene::FrameFormat>());
    }
    const double seconds = o.seconds.value;
    if (o.port < 1 || o.port > 65535 || config.clients < 1 || config.clients > 256 ||
        config.size < 16 || config.size > 8192 || seconds <= 0.0 || seconds > 3600.0) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "--port is required; --clients 1..256, --size 16..8192, "
                                "--seconds (0, 3600]");
    }
    config.port = static_cast<unsigned short>(o.port);
    config.seconds = seconds;
    return base::Ok{};
}

int run_load(const std::vector<std::string>& args) {
    LoadOptions o;
    const po::options_description options = load_options(o);
    auto parsed = parse_options(args, options);
    if (!parsed) {
        return report_usage_error("load", parsed.error());
    }
    if (parsed->count("help") != 0) {
        print_help("load --port P [options]",
                   "N simulated clients on one server, each orbiting the camera and waiting for "
                   "each frame before\nasking for the next. Reports the latency from request sent "
                   "to frame received (p50/p95/p99),\nits server-side split, frames/s, bytes/s and "
                   "errors. The WebSocket URL names the volume\n(/ws?volume=ID), as a cluster's "
                   "proxy routes by it (proto/README.md).",
                   options);
        return 0;
    }
    if (auto status = finish_load_options(*parsed, o); !status) {
        std::fprintf(stderr, "penumbra load: %s\n", status.error().message.c_str());
        return 2;
    }
    const net::LoadReport report = net::run_load(o.config);
    net::print_load_report(o.config, report, stdout);
    return report.ok() ? 0 : 1;
}

}  // namespace penumbra::app
