#include "arguments.hpp"
#include "commands.hpp"
#include "render_options.hpp"

#include <penumbra/base/data_dir.hpp>
#include <penumbra/base/log.hpp>
#include <penumbra/metrics/registry.hpp>
#include <penumbra/net/server.hpp>
#include <penumbra/quality/startup.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/default_preset.hpp>
#include <penumbra/session/scheduler.hpp>
#include <penumbra/session/session.hpp>
#include <penumbra/session/volume_store.hpp>

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace penumbra::app {
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

// A secret from the file `option` names, else from the environment variable; empty when neither
// is given. A secret is not a command-line value, which every user of the machine can read.
base::Result<std::string> read_secret(const Arguments& a, const std::string& option,
                                      const char* variable) {
    std::string secret;
    if (const auto path = a.get(option)) {
        std::ifstream in(*path);
        if (!in) {
            return base::make_error("not_found", "cannot read '" + *path + "'", "--" + option);
        }
        std::stringstream text;
        text << in.rdbuf();
        secret = text.str();
    } else if (const char* value = std::getenv(variable); value != nullptr) {
        secret = value;
    } else {
        return std::string();
    }
    // Editors and `echo` end a file with a newline that is no part of the secret.
    while (!secret.empty() && std::isspace(static_cast<unsigned char>(secret.back())) != 0) {
        secret.pop_back();
    }
    if (secret.empty()) {
        return base::make_error("invalid_argument", "the secret is empty",
                                a.has(option) ? "--" + option : std::string(variable));
    }
    return secret;
}

// The defaults of `penumbra render` and `bench accuracy`: the frame the committed tables were
// measured from.
base::Result<scene::FrameRequest> default_frame(const volume::Volume& volume) {
    auto no_options = Arguments::parse({}, frame_option_names(), frame_flag_names());
    if (!no_options) {
        return no_options.error();
    }
    return frame_request_from(*no_options, volume);
}

void print_serve_usage() {
    std::puts(
            "usage: penumbra serve [options]\n\n"
            "  --data DIR                 folder of volumes to offer; links in it are\n"
            "                             followed (default: the demo folder that\n"
            "                             scripts/demo-data.sh makes, the MRI heads of\n"
            "                             /usr/share/mricron/templates and InVesalius' head\n"
            "                             CT in $XDG_CACHE_HOME/penumbra/volumes or\n"
            "                             ~/.cache/penumbra/volumes; where it is missing,\n"
            "                             the MRI heads alone)\n"
            "  --port P                   TCP port (default 8080; 0 = any free port)\n"
            "  --address A                listen address (default 127.0.0.1)\n"
            "  --web-root DIR             the built web client (default share/penumbra/web\n"
            "                             above the binary: client_web/dist, installed)\n"
            "  --io-threads N             network threads (default 2)\n"
            "  --encode-threads N         JPEG/PNG encoder threads (default 2)\n"
            "  --max-sessions N           (default 64)\n"
            "  --max-sessions-per-client N  sessions one client address may hold (default 16)\n"
            "  --max-sessions-per-connection N  sessions one connection may hold (default 4)\n"
            "  --max-connections-per-client N  WebSocket connections one client address\n"
            "                             may hold open (default 32)\n"
            "  --client-address-header H  behind a proxy: the request header naming the\n"
            "                             client (X-Real-IP, X-Forwarded-For), for per-client\n"
            "                             limits and fair render shares; default: the peer's\n"
            "                             address\n"
            "  --max-image-side N         (default 2048)\n"
            "  --max-slices N             (default 1024)\n"
            "  --max-light-res N          (default 1024)\n"
            "  --max-message-bytes N      (default 65536)\n"
            "  --max-requests-per-second R  per connection (default 120)\n"
            "  --max-frame-work W         shader iterations one frame may ask for: pixels x\n"
            "                             samples per ray x the mode's cost per sample, plus\n"
            "                             light-buffer texels x slices x slab samples\n"
            "                             (default 1e11); larger frames are refused\n"
            "  --volume-memory-mb M       loaded volumes kept in memory (default 4096)\n"
            "  --max-load-mb M            memory one volume load may take (default 8192;\n"
            "                             never more than the machine has available)\n"
            "  --gpu-memory-mb M          volume textures kept on the GPU (default 2048)\n"
            "  --light-buffer-memory-mb M light buffers kept on the GPU; a larger one is\n"
            "                             refused (default 1024)\n"
            "  --supersede-after S        seconds a frame may render before a newer request\n"
            "                             of its session cancels it (default 0.5)\n"
            "  --rescan-interval S        seconds between scans of the data folder (default\n"
            "                             10; a file added at its top is seen sooner)\n"
            "  --ping-interval S          seconds a WebSocket client may be silent before it\n"
            "                             is pinged (default 15)\n"
            "  --ping-timeout S           seconds it then has to answer before it is dropped\n"
            "                             and its session left (default 15)\n"
            "  --default-tf PRESET        transfer function of new sessions (mri_skin)\n"
            "  --default-ct-tf PRESET     ... of new sessions on a CT, in HU (ct_bone)\n"
            "  --quality-table FILE       `bench accuracy` table for sessions that set a "
            "frame\n"
            "                             budget (default docs/accuracy/llvmpipe.json on\n"
            "                             llvmpipe, docs/accuracy/gpu.json elsewhere, from\n"
            "                             share/penumbra/accuracy above the binary, else a\n"
            "                             short table measured at start-up, at most ~1 min,\n"
            "                             and cached in $XDG_CACHE_HOME/penumbra or\n"
            "                             ~/.cache/penumbra for the next start)\n"
            "  --no-quality-measure       never measure at start-up (frame budgets are then\n"
            "                             ignored where no table exists)\n"
            "  --quality-measure          measure the start-up table even where a table\n"
            "                             exists; it is used and cached\n"
            "  --allowed-origins LIST     comma-separated origins (https://host:port) whose\n"
            "                             pages may open the WebSocket besides the server's\n"
            "                             own; * for any. Clients that send no Origin (not\n"
            "                             browsers) are not concerned\n"
            "  --access-token-file FILE   the WebSocket upgrade must carry this file's token\n"
            "                             (/ws?token=...); else $PENUMBRA_ACCESS_TOKEN; none:\n"
            "                             no token asked\n"
            "  --cluster-secret-file FILE owner tokens are derived from session ids with this\n"
            "                             secret (else $PENUMBRA_CLUSTER_SECRET), the same on\n"
            "                             every server of a cluster: an owner whose server\n"
            "                             died resumes its session on another one\n"
            "  --debug-gl                 GL debug output to the log\n"
            "\nThe address prints on start; SIGINT or SIGTERM shuts down cleanly.");
}

// The demo data: scripts/demo-data.sh links the MRI heads beside the CT it converts in the user's
// cache; without it, the heads alone.
std::filesystem::path default_data_folder() {
    std::error_code ec;
    if (const auto folder = demo_data_dir(); folder && std::filesystem::is_directory(*folder, ec)) {
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
    int encode_threads = 2;
    int volume_memory_mb = 4096;
    int max_load_mb = static_cast<int>(volume::LoadOptions{}.max_bytes >> 20);
    int gpu_memory_mb = 2048;
    int light_buffer_memory_mb = 1024;
    std::string data;
    std::string cluster_secret;
    quality::Measure measure = quality::Measure::where_missing;
    std::optional<std::filesystem::path> quality_table;
    bool debug_gl = false;
    session::SchedulerOptions scheduler;
    std::chrono::milliseconds rescan_interval = std::chrono::seconds(10);
};

struct IntegerOption {
    const char* name;
    int* target;
    int min;
    int max;
};

struct DurationOption {
    const char* name;
    std::chrono::milliseconds* target;
    double min_seconds;
    double max_seconds;
};

// serve's whole-number options: each with where it goes and its range.
std::vector<IntegerOption> integer_options(ServeOptions& o) {
    net::ServerConfig& config = o.config;
    protocol::Limits& limits = config.limits;
    return {
            {"port", &o.port, 0, 65535},
            {"io-threads", &config.io_threads, 1, 64},
            {"encode-threads", &o.encode_threads, 1, 64},
            {"max-sessions", &limits.max_sessions, 1, 100000},
            {"max-sessions-per-client", &limits.max_sessions_per_client, 1, 100000},
            {"max-sessions-per-connection", &limits.max_sessions_per_connection, 1, 100000},
            {"max-connections-per-client", &config.max_connections_per_client, 1, 100000},
            {"max-image-side", &limits.max_image_side, 16, 16384},
            {"max-slices", &limits.max_slices, 1, 16384},
            {"max-light-res", &limits.max_light_resolution, 1, 16384},
            {"max-message-bytes", &o.max_message_bytes, 1024, 16 << 20},
            {"volume-memory-mb", &o.volume_memory_mb, 1, 1 << 20},
            {"max-load-mb", &o.max_load_mb, 1, 1 << 24},
            {"gpu-memory-mb", &o.gpu_memory_mb, 1, 1 << 20},
            {"light-buffer-memory-mb", &o.light_buffer_memory_mb, 1, 1 << 20},
    };
}

// serve's options in seconds, likewise.
std::vector<DurationOption> duration_options(ServeOptions& o) {
    return {
            {"ping-interval", &o.config.ping_interval, 0.05, 3600.0},
            {"ping-timeout", &o.config.ping_timeout, 0.05, 3600.0},
            {"supersede-after", &o.scheduler.supersede_running_after, 0.0, 3600.0},
            {"rescan-interval", &o.rescan_interval, 0.1, 86400.0},
    };
}

// The options that take a value: those of the two tables above, and these.
const std::vector<std::string>& serve_option_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> all = {"data",
                                        "address",
                                        "web-root",
                                        "default-tf",
                                        "default-ct-tf",
                                        "quality-table",
                                        "client-address-header",
                                        "allowed-origins",
                                        "access-token-file",
                                        "cluster-secret-file",
                                        "max-requests-per-second",
                                        "max-frame-work"};
        ServeOptions any;
        for (const auto& option : integer_options(any)) {
            all.emplace_back(option.name);
        }
        for (const auto& option : duration_options(any)) {
            all.emplace_back(option.name);
        }
        return all;
    }();
    return names;
}

base::Status read_integers(const Arguments& a, ServeOptions& o) {
    for (const auto& option : integer_options(o)) {
        auto value = a.integer(option.name, *option.target);
        if (!value) {
            return value.error();
        }
        if (*value < option.min || *value > option.max) {
            return base::make_error("invalid_argument",
                                    "must be within " + std::to_string(option.min) + ".." +
                                            std::to_string(option.max),
                                    std::string("--") + option.name);
        }
        *option.target = *value;
    }
    o.config.port = static_cast<unsigned short>(o.port);
    o.config.limits.max_message_bytes = static_cast<std::size_t>(o.max_message_bytes);
    return base::Ok{};
}

base::Status read_numbers(const Arguments& a, ServeOptions& o) {
    protocol::Limits& limits = o.config.limits;
    auto rate = a.number("max-requests-per-second", limits.max_requests_per_second);
    if (!rate || *rate < 1.0) {
        return !rate ? rate.error()
                     : base::make_error("invalid_argument", "must be at least 1",
                                        "--max-requests-per-second");
    }
    limits.max_requests_per_second = *rate;
    auto frame_work = a.number("max-frame-work", limits.max_frame_work);
    if (!frame_work || !(*frame_work >= 1e6)) {
        return !frame_work ? frame_work.error()
                           : base::make_error("invalid_argument", "must be at least 1e6",
                                              "--max-frame-work");
    }
    limits.max_frame_work = *frame_work;
    for (const auto& option : duration_options(o)) {
        const double fallback = std::chrono::duration<double>(*option.target).count();
        auto seconds = a.number(option.name, fallback);
        if (!seconds || !(*seconds >= option.min_seconds && *seconds <= option.max_seconds)) {
            char range[64];
            std::snprintf(range, sizeof range, "must be within %g..%g seconds", option.min_seconds,
                          option.max_seconds);
            return !seconds ? seconds.error()
                            : base::make_error("invalid_argument", range,
                                               std::string("--") + option.name);
        }
        *option.target = std::chrono::milliseconds(static_cast<std::int64_t>(*seconds * 1000.0));
    }
    return base::Ok{};
}

base::Result<ServeOptions> serve_options(const Arguments& a) {
    if (a.has("quality-measure") && (a.has("no-quality-measure") || a.has("quality-table"))) {
        return base::make_error("invalid_argument",
                                "cannot be combined with --no-quality-measure or --quality-table",
                                "--quality-measure");
    }
    ServeOptions o;
    using quality::Measure;
    o.measure = a.has("quality-measure")                                ? Measure::always
                : a.has("no-quality-measure") || a.has("quality-table") ? Measure::never
                                                                        : Measure::where_missing;
    if (const auto table = a.get("quality-table")) {
        o.quality_table = *table;
    }
    o.debug_gl = a.has("debug-gl");
    o.data = a.get("data").value_or(default_data_folder().string());
    net::ServerConfig& config = o.config;
    config.address = a.get("address").value_or("127.0.0.1");
    config.web_root = a.get("web-root").value_or(default_web_root().string());
    config.default_transfer_function =
            a.get("default-tf").value_or(std::string(scene::kDefaultPreset));
    config.default_ct_transfer_function =
            a.get("default-ct-tf").value_or(std::string(scene::kDefaultHounsfieldPreset));
    config.client_address_header = a.get("client-address-header").value_or("");
    if (auto status = read_integers(a, o); !status) {
        return status.error();
    }
    if (auto status = read_numbers(a, o); !status) {
        return status.error();
    }
    if (const auto origins = a.get("allowed-origins")) {
        config.allowed_origins = split_list(*origins);
    }
    auto access_token = read_secret(a, "access-token-file", "PENUMBRA_ACCESS_TOKEN");
    if (!access_token) {
        return access_token.error();
    }
    config.access_token = *access_token;
    auto cluster_secret = read_secret(a, "cluster-secret-file", "PENUMBRA_CLUSTER_SECRET");
    if (!cluster_secret) {
        return cluster_secret.error();
    }
    o.cluster_secret = *cluster_secret;
    return o;
}

// The start-up table is measured in the factory, on the render thread with the renderer that
// will serve: a GL context is current on one thread only, and a second one would cost another
// context (and its eglTerminate could pull the display from under the first). The scheduler
// takes no work, and the server accepts no connection, until the factory returns.
base::Result<std::unique_ptr<session::Scheduler>> start_scheduler(
        const ServeOptions& o, session::VolumeStore& volumes, metrics::Registry& registry,
        quality::StartupMeasurement& measured) {
    const render::RendererOptions renderer_options{
            .shader_dir = {},
            .debug_context = o.debug_gl,
            .volume_memory_budget = static_cast<std::size_t>(o.gpu_memory_mb) << 20,
            .light_buffer_memory_budget = static_cast<std::size_t>(o.light_buffer_memory_mb) << 20,
            .max_frame_work = o.config.limits.max_frame_work,
            .chunk_work = 0.0};
    session::SchedulerOptions scheduler_options = o.scheduler;
    scheduler_options.encode_threads = o.encode_threads;
    quality::OfferedVolumes offered;
    for (const session::VolumeEntry& entry : volumes.list()) {
        offered.ids.push_back(entry.id);
    }
    offered.acquire = [&volumes](const std::string& id) { return volumes.acquire(id); };
    return session::Scheduler::create(
            [renderer_options, measure = o.measure, offered = std::move(offered),
             &measured]() -> base::Result<std::unique_ptr<render::FrameRenderer>> {
                auto renderer = render::Renderer::create(renderer_options);
                if (!renderer) {
                    return renderer.error();
                }
                measured = quality::measure_at_startup(**renderer, measure, offered, default_frame,
                                                       stdout);
                return std::unique_ptr<render::FrameRenderer>(std::move(renderer.value()));
            },
            scheduler_options, registry);
}

volume::LoadOptions load_options(const ServeOptions& o) {
    volume::LoadOptions load;
    load.max_bytes = static_cast<std::uint64_t>(o.max_load_mb) << 20;
    return load;
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

const std::vector<std::string>& serve_flag_names() {
    static const std::vector<std::string> names = {"help", "debug-gl", "quality-measure",
                                                   "no-quality-measure"};
    return names;
}

}  // namespace

int run_serve(const std::vector<std::string>& args) {
    auto parsed = Arguments::parse(args, serve_option_names(), serve_flag_names());
    if (!parsed) {
        std::fprintf(stderr, "penumbra serve: %s (see --help)\n",
                     parsed.error().to_string().c_str());
        return 2;
    }
    if (parsed->has("help")) {
        print_serve_usage();
        return 0;
    }
    auto options = serve_options(*parsed);
    if (!options) {
        return fail(options.error());
    }
    net::ServerConfig& config = options->config;
    protocol::Limits& limits = config.limits;
    session::VolumeStore volumes(options->data,
                                 static_cast<std::size_t>(options->volume_memory_mb) << 20,
                                 load_options(*options), options->rescan_interval);
    if (auto status = volumes.scan(); !status) {
        return fail(status.error());
    }
    std::printf("data:     %s (%zu volumes", options->data.c_str(), volumes.list().size());
    if (const std::size_t skipped = volumes.skipped().size(); skipped > 0) {
        std::printf(", %zu files skipped, each logged with why", skipped);
    }
    std::printf(")\n");

    metrics::Registry registry;
    quality::StartupMeasurement measured;
    auto scheduler = start_scheduler(*options, volumes, registry, measured);
    if (!scheduler) {
        return fail(scheduler.error());
    }
    const render::RendererInfo& info = (*scheduler)->renderer_info();
    std::printf("gl:       %s | %s | %s\n", info.renderer.c_str(), info.version.c_str(),
                info.platform.c_str());

    auto table = quality_table(*options, measured, info);
    if (!table) {
        return fail(table.error());
    }
    config.quality_table = *table;

    const std::string& secret = options->cluster_secret;
    session::SessionRegistry sessions(
            limits.max_sessions,
            secret.empty() ? session::OwnerTokens() : session::OwnerTokens(secret),
            limits.max_sessions_per_client, limits.max_sessions_per_connection);
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
