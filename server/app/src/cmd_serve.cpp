#include "commands.hpp"

#include <penumbra/base/data_dir.hpp>
#include <penumbra/base/log.hpp>
#include <penumbra/base/secret.hpp>
#include <penumbra/base/text.hpp>
#include <penumbra/cli/frame_options.hpp>
#include <penumbra/cli/options.hpp>
#include <penumbra/encode/movie.hpp>
#include <penumbra/metrics/registry.hpp>
#include <penumbra/net/server.hpp>
#include <penumbra/quality/startup.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/default_preset.hpp>
#include <penumbra/session/scheduler.hpp>
#include <penumbra/session/session.hpp>
#include <penumbra/session/volume_store.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

namespace penumbra::app {

using namespace cli;

namespace {

int fail(const base::Error& error) {
    return report_failure("serve", error);
}

// The built web client (share/penumbra/web: installed, or in a build tree a link to
// client_web/dist), when it has been built.
std::filesystem::path default_web_root() {
    const auto built = base::data_dir("web");
    return built && std::filesystem::exists(*built / "index.html") ? *built
                                                                   : std::filesystem::path();
}

// The secret from the file `option` names, else from the environment variable.
base::Result<std::string> read_secret(const po::variables_map& a, const std::string& option,
                                      const char* variable) {
    std::optional<std::filesystem::path> file;
    if (a.count(option) != 0) {
        file = a[option].as<std::string>();
    }
    return base::read_secret(file, variable, "--" + option);
}

// The demo data: scripts/demo-data.sh links the MRI heads beside the CT it converts in the user's
// cache; without it, the heads alone.
std::filesystem::path default_data_folder() {
    std::error_code ec;
    if (const auto folder = base::demo_data_dir();
        folder && std::filesystem::is_directory(*folder, ec)) {
        return *folder;
    }
    return mricron_templates;
}

// Everything `serve` is told, checked.
struct ServeOptions {
    net::ServerConfig config;
    // Read as whole numbers, then put into config.
    int port = net::ServerConfig{}.port;
    int max_message_bytes = static_cast<int>(protocol::Limits{}.max_message_bytes);
    std::size_t volume_memory = std::size_t{4} << 30;
    volume::LoadOptions load;
    render::RendererOptions renderer;
    std::string data;
    std::string web_root;
    std::string cluster_secret;
    quality::Measure measure = quality::Measure::where_missing;
    std::optional<std::filesystem::path> quality_table;
    session::SchedulerOptions scheduler;
    session::ScanOptions scan;
};

po::options_description network_options(ServeOptions& o) {
    net::ServerConfig& c = o.config;
    protocol::Limits& limits = c.limits;
    po::options_description options = option_group("network and limits");
    options.add_options()("port", whole_number(&o.port, 0, 65535), "TCP port (0 = any free port)")(
            "address", po::value(&c.address)->value_name("A")->default_value(c.address),
            "listen address")("io-threads", whole_number(&c.io_threads, 1, 64), "network threads")(
            "encode-threads", whole_number(&o.scheduler.encode_threads, 1, 64),
            "JPEG/PNG encoder threads")(
            "frames-in-flight", whole_number(&o.scheduler.frames_in_flight, 0, 4),
            "frames the render thread submits before it waits for the oldest; 0: the device's "
            "(2 on a GPU, 1 on a software rasteriser)")(
            "max-sessions", whole_number(&limits.max_sessions, 1, 100000), "sessions in all")(
            "max-sessions-per-client", whole_number(&limits.max_sessions_per_client, 1, 100000),
            "sessions one client address may hold")(
            "max-sessions-per-connection",
            whole_number(&limits.max_sessions_per_connection, 1, 100000),
            "sessions one connection may hold")(
            "max-connections-per-client", whole_number(&c.max_connections_per_client, 1, 100000),
            "WebSocket connections one client address may hold open")(
            "client-address-header", po::value(&c.client_address_header)->value_name("H"),
            "behind a proxy: the request header naming the client (X-Real-IP, X-Forwarded-For), "
            "for per-client limits and fair render shares; default: the peer's address")(
            "max-image-side", whole_number(&limits.max_image_side, 16, 16384), "pixels")(
            "max-export-side", whole_number(&limits.max_export_side, 16, 16384),
            "pixels of an exported still, rendered in tiles")(
            "max-movie-side", whole_number(&limits.max_movie_side, 16, 8192),
            "pixels of an exported movie's side")("max-movie-frames",
                                                  whole_number(&limits.max_movie_frames, 0, 100000),
                                                  "frames of an exported movie; 0: none")(
            "max-slices", whole_number(&limits.max_slices, 1, 16384), "light slices")(
            "max-light-res", whole_number(&limits.max_light_resolution, 1, 16384),
            "light-buffer resolution")("max-message-bytes",
                                       whole_number(&o.max_message_bytes, 1024, 16 << 20),
                                       "a client message's size")(
            "max-requests-per-second", at_least(&limits.max_requests_per_second, 1.0),
            "per connection")(
            "max-frame-work", at_least(&limits.max_frame_work, 1e6),
            "shader iterations one frame may ask for: pixels x samples per ray x the mode's cost "
            "per sample, plus light-buffer texels x slices x slab samples; larger frames are "
            "refused")("supersede-after",
                       seconds(&o.scheduler.supersede_running_after, 0.0, 3600.0),
                       "seconds a frame may render before a newer request of its session cancels "
                       "it")("ping-interval", seconds(&c.ping_interval, 0.05, 3600.0),
                             "seconds a WebSocket client may be silent before it is pinged")(
            "ping-timeout", seconds(&c.ping_timeout, 0.05, 3600.0),
            "seconds it then has to answer before it is dropped and its session left");
    return options;
}

po::options_description data_options(ServeOptions& o) {
    net::ServerConfig& c = o.config;
    po::options_description options = option_group("data, memory and access");
    options.add_options()("help", "this text")(
            "data", po::value(&o.data)->value_name("DIR")->default_value(o.data),
            "folder of volumes to offer; links in it are followed to files, and to folders inside "
            "it or --allow-links-to (default: the demo folder that "
            "scripts/demo-data.sh makes, else the MRI heads of Debian's mricron-data)")(
            "web-root", po::value(&o.web_root)->value_name("DIR"),
            "the built web client (default share/penumbra/web above the binary: client_web/dist, "
            "installed)")("rescan-interval", seconds(&o.scan.rescan_interval, 0.1, 86400.0),
                          "seconds between scans of the data folder (a file added at its top is "
                          "seen sooner)")(
            "allow-links-to", po::value<std::string>()->value_name("LIST"),
            "comma-separated folders outside the data folder that links in it may lead to "
            "(links to files are followed anywhere; links to other folders are skipped)")(
            "scan-max-entries", whole_number(&o.scan.max_entries, 1, 100'000'000),
            "files and folders one scan of the data folder may see before it stops")(
            "scan-max-seconds", seconds(&o.scan.max_time, 0.1, 86400.0),
            "CPU seconds one scan of the data folder may use before it stops")(
            "volume-memory-mb", megabytes(&o.volume_memory, 1 << 20),
            "loaded volumes kept in memory")(
            "max-load-mb", megabytes(&o.load.max_bytes, 1 << 24),
            "memory one volume load may take (never more than the machine has available)")(
            "gpu-memory-mb", megabytes(&o.renderer.volume_memory_budget, 1 << 20),
            "volume textures kept on the GPU")(
            "light-buffer-memory-mb", megabytes(&o.renderer.light_buffer_memory_budget, 1 << 20),
            "light buffers kept on the GPU; a larger one is refused")(
            "default-tf",
            po::value(&c.default_transfer_function)
                    ->value_name("PRESET")
                    ->default_value(c.default_transfer_function),
            "transfer function of new sessions")(
            "default-ct-tf",
            po::value(&c.default_ct_transfer_function)
                    ->value_name("PRESET")
                    ->default_value(c.default_ct_transfer_function),
            "... of new sessions on a CT, in HU")(
            "allowed-origins", po::value<std::string>()->value_name("LIST"),
            "comma-separated origins (https://host:port) whose pages may open the WebSocket "
            "besides the server's own; * for any. Clients that send no Origin (not browsers) are "
            "not concerned")("access-token-file", po::value<std::string>()->value_name("FILE"),
                             "the WebSocket upgrade must carry this file's token (/ws?token=...); "
                             "else $PENUMBRA_ACCESS_TOKEN; none: no token asked")(
            "cluster-secret-file", po::value<std::string>()->value_name("FILE"),
            "owner tokens are derived from session ids with this secret (else "
            "$PENUMBRA_CLUSTER_SECRET), the same on every server of a cluster: an owner whose "
            "server died resumes its session on another one")("debug-gl",
                                                              "GL debug output to the log");
    return options;
}

po::options_description quality_options() {
    po::options_description options = option_group("frame budgets");
    options.add_options()(
            "quality-table", po::value<std::string>()->value_name("FILE"),
            "`bench accuracy` table for sessions that set a frame budget (default "
            "docs/accuracy/llvmpipe.json on llvmpipe, docs/accuracy/gpu.json elsewhere, from "
            "share/penumbra/accuracy above the binary, else a short table measured at start-up, "
            "at most ~1 min, and cached in $XDG_CACHE_HOME/penumbra or ~/.cache/penumbra)")(
            "no-quality-measure",
            "never measure at start-up (frame budgets are then ignored where no table exists)")(
            "quality-measure",
            "measure the start-up table even where a table exists; it is used and cached");
    return options;
}

// What the options leave to be read or checked together.
base::Status finish_options(const po::variables_map& a, ServeOptions& o) {
    if (a.count("quality-measure") != 0 &&
        (a.count("no-quality-measure") != 0 || a.count("quality-table") != 0)) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "cannot be combined with --no-quality-measure or --quality-table",
                                "--quality-measure");
    }
    using quality::Measure;
    o.measure = a.count("quality-measure") != 0 ? Measure::always
                : a.count("no-quality-measure") + a.count("quality-table") != 0
                        ? Measure::never
                        : Measure::where_missing;
    if (a.count("quality-table") != 0) {
        o.quality_table = a["quality-table"].as<std::string>();
    }
    o.renderer.debug_context = a.count("debug-gl") != 0;
    o.config.web_root = o.web_root;
    o.config.port = static_cast<unsigned short>(o.port);
    o.config.limits.max_message_bytes = static_cast<std::size_t>(o.max_message_bytes);
    if (!encode::writes_movies()) {
        o.config.limits.max_movie_frames = 0;  // hello says so; export_movie is refused
    }
    if (a.count("allow-links-to") != 0) {
        for (const std::string& root : base::split_list(a["allow-links-to"].as<std::string>())) {
            // A root that cannot be resolved would allow nothing; the operator hears so now.
            if (auto status = session::check_data_folder(root); !status) {
                return base::make_error(base::ErrorCode::not_found,
                                        "'" + root + "' is not a folder this server can read",
                                        "--allow-links-to");
            }
            o.scan.link_roots.emplace_back(root);
        }
    }
    if (a.count("allowed-origins") != 0) {
        o.config.allowed_origins = base::split_list(a["allowed-origins"].as<std::string>());
    }
    auto access_token = read_secret(a, "access-token-file", "PENUMBRA_ACCESS_TOKEN");
    if (!access_token) {
        return access_token.error();
    }
    o.config.access_token = *access_token;
    auto cluster_secret = read_secret(a, "cluster-secret-file", "PENUMBRA_CLUSTER_SECRET");
    if (!cluster_secret) {
        return cluster_secret.error();
    }
    o.cluster_secret = *cluster_secret;
    return base::Ok{};
}

// The start-up table is measured in the factory, on the render thread with the renderer that
// will serve: a GL context is current on one thread only, and a second one would cost another
// context (and its eglTerminate could pull the display from under the first). The scheduler
// takes no work, and the server accepts no connection, until the factory returns.
base::Result<std::unique_ptr<session::Scheduler>> start_scheduler(
        const ServeOptions& o, session::VolumeStore& volumes, metrics::Registry& registry,
        quality::StartupMeasurement& measured) {
    render::RendererOptions renderer_options = o.renderer;
    renderer_options.max_frame_work = o.config.limits.max_frame_work;
    quality::OfferedVolumes offered;
    // Only a measurement waits for the folder's first scan; a server with its table starts at once.
    offered.ids = [&volumes] {
        volumes.wait_for_first_pass();
        std::vector<std::string> ids;
        for (const session::VolumeEntry& entry : volumes.list()) {
            if (!entry.label_map) {  // an atlas's ids drawn as values are no scan to measure on
                ids.push_back(entry.id);
            }
        }
        return ids;
    };
    offered.acquire = [&volumes](const std::string& id) { return volumes.acquire(id); };
    return session::Scheduler::create(
            [renderer_options, measure = o.measure, offered = std::move(offered),
             &measured]() -> base::Result<std::unique_ptr<render::FrameRenderer>> {
                auto renderer = render::Renderer::create(renderer_options);
                if (!renderer) {
                    return renderer.error();
                }
                measured = quality::measure_at_startup(**renderer, measure, offered,
                                                       default_frame_request, stdout);
                return std::unique_ptr<render::FrameRenderer>(std::move(renderer.value()));
            },
            o.scheduler, registry);
}

// The accuracy table sessions with a frame budget choose from; null: budgets are ignored.
base::Result<std::shared_ptr<const quality::Table>> quality_table(
        const ServeOptions& o, const quality::StartupMeasurement& measured,
        const render::RendererInfo& info) {
    auto table = quality::serve_table(o.quality_table, measured, quality::table_paths(info));
    if (!table) {
        return table.error();
    }
    for (const std::string& note : table->notes) {
        std::printf("quality:  %s\n", note.c_str());
    }
    return table->table;
}

void print_access(const net::ServerConfig& config, bool cluster) {
    std::printf("access:   %s; WebSocket pages from %s\n",
                config.access_token.empty() ? "no token asked" : "token asked on /ws",
                config.allowed_origins.empty()
                        ? "this server's own origin only"
                        : ("its own origin and " + std::to_string(config.allowed_origins.size()) +
                           " listed")
                                  .c_str());
    if (cluster) {
        std::printf("cluster:  owner tokens derived from the cluster secret\n");
    }
}

}  // namespace

int run_serve(const std::vector<std::string>& args) {
    ServeOptions o;
    o.data = default_data_folder().string();
    o.web_root = default_web_root().string();
    po::options_description options = data_options(o);
    options.add(network_options(o)).add(quality_options());
    auto parsed = parse_options(args, options);
    if (!parsed) {
        return report_usage_error("serve", parsed.error());
    }
    if (parsed->count("help") != 0) {
        print_help("serve [options]",
                   "The address prints on start; SIGINT or SIGTERM shuts down cleanly.", options);
        return 0;
    }
    if (auto status = finish_options(*parsed, o); !status) {
        return fail(status.error());
    }
    net::ServerConfig& config = o.config;
    protocol::Limits& limits = config.limits;
    // The folder is walked in the background: whatever it holds, the server listens at once.
    if (auto status = session::check_data_folder(o.data); !status) {
        return fail(status.error());
    }
    metrics::Registry registry;
    o.scan.metrics = &registry;
    session::VolumeStore volumes(o.data, o.volume_memory, o.load, o.scan);
    std::printf("data:     %s (scanned in the background; skipped files are logged with why)\n",
                o.data.c_str());
    quality::StartupMeasurement measured;
    auto scheduler = start_scheduler(o, volumes, registry, measured);
    if (!scheduler) {
        return fail(scheduler.error());
    }
    const render::RendererInfo& info = (*scheduler)->renderer_info();
    std::printf("gl:       %s | %s | %s\n", info.renderer.c_str(), info.version.c_str(),
                info.platform.c_str());

    auto table = quality_table(o, measured, info);
    if (!table) {
        return fail(table.error());
    }

    const std::string& secret = o.cluster_secret;
    session::SessionRegistry sessions(
            limits.max_sessions,
            secret.empty() ? session::OwnerTokens() : session::OwnerTokens(secret),
            limits.max_sessions_per_client, limits.max_sessions_per_connection, *table);
    print_access(config, !secret.empty());
    auto server = net::Server::start(config, {volumes, sessions, **scheduler, registry});
    if (!server) {
        return fail(server.error());
    }
    std::printf("serving:  http://%s:%u/  (WebSocket ws://%s:%u/ws)\n", config.address.c_str(),
                (*server)->port(), config.address.c_str(), (*server)->port());
    std::fflush(stdout);
    (*server)->wait_for_shutdown_signal();
    (*server)->stop();
    (*scheduler)->stop();
    std::puts("stopped");
    return 0;
}

}  // namespace penumbra::app
