#include "accuracy_sweep.hpp"
#include "arguments.hpp"
#include "commands.hpp"

#include <penumbra/base/data_dir.hpp>
#include <penumbra/base/log.hpp>
#include <penumbra/metrics/registry.hpp>
#include <penumbra/net/server.hpp>
#include <penumbra/protocol/scene_json.hpp>
#include <penumbra/render/renderer.hpp>
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

// The demo data: scripts/demo-data.sh links the MRI heads beside the CT it converts in the user's
// cache; without it, the heads alone.
std::filesystem::path default_data_folder() {
    std::error_code ec;
    if (const auto cache = base::user_cache_dir();
        cache && std::filesystem::is_directory(*cache / "volumes", ec)) {
        return *cache / "volumes";
    }
    return mricron_templates;
}

// The built web client (share/penumbra/web: installed, or in a build tree a link to
// client_web/dist), when it has been built.
std::filesystem::path default_web_root() {
    const auto built = base::data_dir("web");
    return built && std::filesystem::exists(*built / "index.html") ? *built
                                                                   : std::filesystem::path();
}

using QualityTable = std::shared_ptr<const std::vector<scene::QualitySample>>;

// The table committed for this kind of device (DESIGN.md §1): measured by `bench accuracy`.
// share/penumbra/accuracy holds docs/accuracy's tables (installed, or linked in a build tree).
std::filesystem::path committed_table_path(const render::RendererInfo& info) {
    const std::filesystem::path name = info.gpu_timer_queries ? "gpu.json" : "llvmpipe.json";
    return base::data_dir("accuracy").value_or("share/penumbra/accuracy") / name;
}

// Where a table measured at start-up is kept, one file per GL_RENDERER so that the cost is paid
// once per kind of device: $XDG_CACHE_HOME/penumbra, else ~/.cache/penumbra; nowhere without
// either variable.
std::optional<std::filesystem::path> cached_table_path(const std::string& gl_renderer) {
    const std::optional<std::filesystem::path> cache = base::user_cache_dir();
    if (!cache) {
        return std::nullopt;
    }
    const std::filesystem::path& folder = *cache;
    // "llvmpipe (LLVM 15.0.6, 256 bits)" -> "llvmpipe_LLVM_15.0.6_256_bits": a file name on
    // any file system, still readable.
    std::string name;
    for (const char c : gl_renderer) {
        if (std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '.' || c == '-') {
            name += c;
        } else if (!name.empty() && name.back() != '_') {
            name += '_';
        }
    }
    while (!name.empty() && name.back() == '_') {
        name.pop_back();
    }
    return folder / ("quality-" + (name.empty() ? std::string("unknown") : name) + ".json");
}

base::Result<QualityTable> parse_table(const std::string& text, const std::string& where) {
    auto table = protocol::parse_quality_table(text, where);
    if (!table) {
        return table.error();
    }
    return std::make_shared<const std::vector<scene::QualitySample>>(std::move(table.value()));
}

// Nothing when the file cannot be opened; an error when it is not a table.
std::optional<base::Result<QualityTable>> read_table_file(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) {
        return std::nullopt;
    }
    std::stringstream text;
    text << in.rdbuf();
    return parse_table(text.str(), path.string());
}

// Through a temporary file and a rename, so a server starting at the same time never reads half
// a table.
base::Status write_table_file(const std::filesystem::path& path, const std::string& text) {
    std::error_code error;
    std::filesystem::create_directories(path.parent_path(), error);
    const std::filesystem::path temporary = path.string() + ".tmp";
    {
        std::ofstream out(temporary);
        out << text << '\n';
        if (!out) {
            return base::make_error("io_error", "cannot write '" + temporary.string() + "'",
                                    "quality cache");
        }
    }
    std::filesystem::rename(temporary, path, error);
    if (error) {
        std::filesystem::remove(temporary, error);
        return base::make_error("io_error", "cannot write '" + path.string() + "'",
                                "quality cache");
    }
    return base::Ok{};
}

// "a, b,c" -> {"a", "b", "c"}.
std::vector<std::string> split_list(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream stream(text);
    std::string item;
    while (std::getline(stream, item, ',')) {
        const auto first = item.find_first_not_of(" \t");
        const auto last = item.find_last_not_of(" \t");
        if (first != std::string::npos) {
            out.push_back(item.substr(first, last - first + 1));
        }
    }
    return out;
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

enum class Measure { never, where_missing, always };

// What the render thread measured before taking work.
struct StartupMeasurement {
    std::optional<accuracy::StartupTable> table;
    std::string volume;
    std::optional<base::Error> error;
};

// Measures the start-up table on the renderer that will serve, on its own thread (its GL context
// is current there only): ch2, the default volume everywhere, where the data folder has it, else
// the first volume offered.
StartupMeasurement measure_at_startup(render::FrameRenderer& renderer,
                                      session::VolumeStore& volumes, bool forced) {
    StartupMeasurement result;
    const std::vector<session::VolumeEntry> entries = volumes.list();
    if (entries.empty()) {
        result.error = base::make_error("no_volume", "no volume to measure on", "--data");
        return result;
    }
    std::string id = entries.front().id;
    for (const session::VolumeEntry& entry : entries) {
        if (entry.id == "ch2.nii.gz") {
            id = entry.id;
        }
    }
    auto volume = volumes.acquire(id);
    if (!volume) {
        result.error = volume.error();
        return result;
    }
    result.volume = id;
    const accuracy::StartupOptions options = accuracy::startup_options();
    std::printf("quality:  %s a short table on %s at %dx%d (at most ~%.0f s)\n",
                forced ? "--quality-measure: measuring" : "no table for this device: measuring",
                id.c_str(), options.side, options.side, options.time_limit_s);
    std::fflush(stdout);
    auto table = accuracy::measure_startup_table(renderer, *volume, options);
    if (!table) {
        result.error = table.error();
        return result;
    }
    result.table = std::move(table.value());
    return result;
}

// The measured table as the server uses it, cached for the next start where there is a cache.
base::Result<QualityTable> adopt_measured(const StartupMeasurement& measured,
                                          const std::optional<std::filesystem::path>& cache) {
    const accuracy::StartupTable& startup = *measured.table;
    const accuracy::Table& table = startup.table;
    const std::string text = accuracy::table_json(
            table, accuracy::choose_presets(table.points, accuracy::default_budgets(table.points)));
    auto parsed = parse_table(text, "the start-up measurement");
    if (!parsed) {
        return parsed.error();
    }
    std::printf("quality:  measured %zu settings on %s at %dx%d in %.1f s (%s time)%s\n",
                table.points.size(), measured.volume.c_str(), table.width, table.height,
                startup.seconds, accuracy::timing_name(table),
                startup.complete ? "" : "; stopped at the time limit, serving with those");
    if (!cache) {
        std::printf("quality:  not cached (neither XDG_CACHE_HOME nor HOME is set)\n");
    } else if (auto status = write_table_file(*cache, text); !status) {
        std::printf("quality:  not cached: %s\n", status.error().to_string().c_str());
    } else {
        std::printf("quality:  cached in %s for the next start\n", cache->c_str());
    }
    return parsed;
}

}  // namespace

int run_serve(const std::vector<std::string>& args) {
    auto parsed = Arguments::parse(args,
                                   {"data",
                                    "port",
                                    "address",
                                    "web-root",
                                    "io-threads",
                                    "encode-threads",
                                    "max-sessions",
                                    "max-image-side",
                                    "max-slices",
                                    "max-light-res",
                                    "max-message-bytes",
                                    "max-requests-per-second",
                                    "max-frame-work",
                                    "volume-memory-mb",
                                    "max-load-mb",
                                    "gpu-memory-mb",
                                    "light-buffer-memory-mb",
                                    "default-tf",
                                    "quality-table",
                                    "ping-interval",
                                    "ping-timeout",
                                    "max-sessions-per-client",
                                    "max-sessions-per-connection",
                                    "client-address-header",
                                    "allowed-origins",
                                    "access-token-file",
                                    "cluster-secret-file"},
                                   {"help", "debug-gl", "quality-measure", "no-quality-measure"});
    if (!parsed) {
        std::fprintf(stderr, "penumbra serve: %s (see --help)\n",
                     parsed.error().to_string().c_str());
        return 2;
    }
    const Arguments& a = *parsed;
    if (a.has("help")) {
        std::puts(
                "usage: penumbra serve [options]\n\n"
                "  --data DIR                 folder of volumes to offer; links in it are\n"
                "                             followed (default: the demo folder that\n"
                "                             scripts/demo-data.sh makes, the MRI heads of\n"
                "                             /usr/share/mricron/templates and InVesalius' head\n"
                "                             CT in $XDG_CACHE_HOME/penumbra/volumes or\n"
                "                             ~/.cache/penumbra/volumes; where it is missing,\n"
                "                             /usr/share/mricron/templates)\n"
                "  --port P                   TCP port (default 8080; 0 = any free port)\n"
                "  --address A                listen address (default 127.0.0.1)\n"
                "  --web-root DIR             the built web client (default share/penumbra/web\n"
                "                             above the binary: client_web/dist, installed)\n"
                "  --io-threads N             network threads (default 2)\n"
                "  --encode-threads N         JPEG/PNG encoder threads (default 2)\n"
                "  --max-sessions N           (default 64)\n"
                "  --max-sessions-per-client N  sessions one client address may hold (default 16)\n"
                "  --max-sessions-per-connection N  sessions one connection may hold (default 4)\n"
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
                "  --ping-interval S          seconds a WebSocket client may be silent before it\n"
                "                             is pinged (default 15)\n"
                "  --ping-timeout S           seconds it then has to answer before it is dropped\n"
                "                             and its session left (default 15)\n"
                "  --default-tf PRESET        transfer function of new sessions (mri_skin)\n"
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
        return 0;
    }
    if (a.has("quality-measure") && (a.has("no-quality-measure") || a.has("quality-table"))) {
        return fail(base::make_error("invalid_argument",
                                     "cannot be combined with --no-quality-measure or "
                                     "--quality-table",
                                     "--quality-measure"));
    }
    const Measure measure = a.has("quality-measure") ? Measure::always
                            : a.has("no-quality-measure") || a.has("quality-table")
                                    ? Measure::never
                                    : Measure::where_missing;

    net::ServerConfig config;
    config.address = a.get("address").value_or("127.0.0.1");
    config.web_root = a.get("web-root").value_or(default_web_root().string());
    config.default_transfer_function = a.get("default-tf").value_or("mri_skin");
    config.client_address_header = a.get("client-address-header").value_or("");
    protocol::Limits& limits = config.limits;

    struct IntegerOption {
        const char* name;
        int* target;
        int min;
        int max;
    };

    int port = 8080;
    int encode_threads = 2;
    int volume_memory_mb = 4096;
    int max_load_mb = static_cast<int>(volume::LoadOptions{}.max_bytes >> 20);
    int gpu_memory_mb = 2048;
    int light_buffer_memory_mb = 1024;
    int max_message_bytes = static_cast<int>(limits.max_message_bytes);
    const IntegerOption integers[] = {
            {"port", &port, 0, 65535},
            {"io-threads", &config.io_threads, 1, 64},
            {"encode-threads", &encode_threads, 1, 64},
            {"max-sessions", &limits.max_sessions, 1, 100000},
            {"max-sessions-per-client", &limits.max_sessions_per_client, 1, 100000},
            {"max-sessions-per-connection", &limits.max_sessions_per_connection, 1, 100000},
            {"max-image-side", &limits.max_image_side, 16, 16384},
            {"max-slices", &limits.max_slices, 1, 16384},
            {"max-light-res", &limits.max_light_resolution, 1, 16384},
            {"max-message-bytes", &max_message_bytes, 1024, 16 << 20},
            {"volume-memory-mb", &volume_memory_mb, 1, 1 << 20},
            {"max-load-mb", &max_load_mb, 1, 1 << 24},
            {"gpu-memory-mb", &gpu_memory_mb, 1, 1 << 20},
            {"light-buffer-memory-mb", &light_buffer_memory_mb, 1, 1 << 20},
    };
    for (const auto& option : integers) {
        auto value = a.integer(option.name, *option.target);
        if (!value || *value < option.min || *value > option.max) {
            return fail(!value ? value.error()
                               : base::make_error("invalid_argument",
                                                  "must be within " + std::to_string(option.min) +
                                                          ".." + std::to_string(option.max),
                                                  std::string("--") + option.name));
        }
        *option.target = *value;
    }
    config.port = static_cast<unsigned short>(port);
    limits.max_message_bytes = static_cast<std::size_t>(max_message_bytes);
    auto rate = a.number("max-requests-per-second", limits.max_requests_per_second);
    if (!rate || *rate < 1.0) {
        return fail(!rate ? rate.error()
                          : base::make_error("invalid_argument", "must be at least 1",
                                             "--max-requests-per-second"));
    }
    limits.max_requests_per_second = *rate;
    auto frame_work = a.number("max-frame-work", limits.max_frame_work);
    if (!frame_work || !(*frame_work >= 1e6)) {
        return fail(!frame_work ? frame_work.error()
                                : base::make_error("invalid_argument", "must be at least 1e6",
                                                   "--max-frame-work"));
    }
    limits.max_frame_work = *frame_work;
    for (const auto& [name, target] : {std::pair{"ping-interval", &config.ping_interval},
                                       {"ping-timeout", &config.ping_timeout}}) {
        const double fallback = std::chrono::duration<double>(*target).count();
        auto seconds = a.number(name, fallback);
        if (!seconds || *seconds < 0.05 || *seconds > 3600.0) {
            return fail(!seconds ? seconds.error()
                                 : base::make_error("invalid_argument",
                                                    "must be within 0.05..3600 seconds",
                                                    std::string("--") + name));
        }
        *target = std::chrono::milliseconds(static_cast<std::int64_t>(*seconds * 1000.0));
    }
    if (const auto origins = a.get("allowed-origins")) {
        config.allowed_origins = split_list(*origins);
    }
    auto access_token = read_secret(a, "access-token-file", "PENUMBRA_ACCESS_TOKEN");
    if (!access_token) {
        return fail(access_token.error());
    }
    config.access_token = *access_token;
    auto cluster_secret = read_secret(a, "cluster-secret-file", "PENUMBRA_CLUSTER_SECRET");
    if (!cluster_secret) {
        return fail(cluster_secret.error());
    }

    const std::string data = a.get("data").value_or(default_data_folder().string());
    volume::LoadOptions load_options;
    load_options.max_bytes = static_cast<std::uint64_t>(max_load_mb) << 20;
    session::VolumeStore volumes(data, static_cast<std::size_t>(volume_memory_mb) << 20,
                                 load_options);
    if (auto status = volumes.scan(); !status) {
        return fail(status.error());
    }
    std::printf("data:     %s (%zu volumes", data.c_str(), volumes.list().size());
    if (const std::size_t skipped = volumes.skipped().size(); skipped > 0) {
        std::printf(", %zu files skipped, each logged with why", skipped);
    }
    std::printf(")\n");

    metrics::Registry registry;
    const render::RendererOptions renderer_options{
            .shader_dir = {},
            .debug_context = a.has("debug-gl"),
            .volume_memory_budget = static_cast<std::size_t>(gpu_memory_mb) << 20,
            .light_buffer_memory_budget = static_cast<std::size_t>(light_buffer_memory_mb) << 20,
            .max_frame_work = limits.max_frame_work,
            .chunk_work = 0.0};
    // The start-up table is measured in the factory, on the render thread with the renderer that
    // will serve: a GL context is current on one thread only, and a second one would cost another
    // context (and its eglTerminate could pull the display from under the first). The scheduler
    // takes no work, and the server accepts no connection, until the factory returns.
    StartupMeasurement measured;
    auto scheduler = session::Scheduler::create(
            [renderer_options, measure, &volumes,
             &measured]() -> base::Result<std::unique_ptr<render::FrameRenderer>> {
                auto renderer = render::Renderer::create(renderer_options);
                if (!renderer) {
                    return renderer.error();
                }
                const render::RendererInfo& info = (*renderer)->info();
                const auto cache = cached_table_path(info.renderer);
                const bool have_table = std::filesystem::exists(committed_table_path(info)) ||
                                        (cache && std::filesystem::exists(*cache));
                if (measure == Measure::always ||
                    (measure == Measure::where_missing && !have_table)) {
                    measured = measure_at_startup(**renderer, volumes, measure == Measure::always);
                }
                return std::unique_ptr<render::FrameRenderer>(std::move(renderer.value()));
            },
            {.encode_threads = encode_threads}, registry);
    if (!scheduler) {
        return fail(scheduler.error());
    }
    const render::RendererInfo& info = (*scheduler)->renderer_info();
    std::printf("gl:       %s | %s | %s\n", info.renderer.c_str(), info.version.c_str(),
                info.platform.c_str());
    limits.max_slices = std::min(limits.max_slices, info.max_array_texture_layers);
    limits.max_light_resolution = std::min(limits.max_light_resolution, info.max_texture_size);
    limits.max_image_side = std::min(limits.max_image_side, info.max_texture_size);

    // In order: --quality-table, the start-up measurement, the committed table, the cached one.
    const std::filesystem::path committed = committed_table_path(info);
    const std::optional<std::filesystem::path> cache = cached_table_path(info.renderer);
    if (const auto path = a.get("quality-table")) {
        auto table = read_table_file(*path);
        if (!table) {
            return fail(base::make_error("not_found", "cannot read the quality table", *path));
        }
        if (!*table) {
            return fail(table->error());
        }
        config.quality_table = table->value();
        std::printf("quality:  %zu measured settings from %s\n", config.quality_table->size(),
                    path->c_str());
    } else if (measured.table) {
        // Our own JSON failing to parse would be a bug, but not one worth refusing to serve for.
        if (auto table = adopt_measured(measured, cache)) {
            config.quality_table = table.value();
        } else {
            std::printf(
                    "quality:  the measured table was not usable (%s); frame budgets are "
                    "ignored\n",
                    table.error().to_string().c_str());
        }
    } else {
        if (measured.error) {
            std::printf("quality:  nothing measured at start-up: %s\n",
                        measured.error->to_string().c_str());
        }
        const bool use_cache = !std::filesystem::exists(committed) && cache;
        const std::filesystem::path found = use_cache ? *cache : committed;
        if (auto table = read_table_file(found); table && !*table && use_cache) {
            // A cache is ours to replace: serving without budgets beats not serving.
            std::printf("quality:  ignoring the cached table (%s); remove it to measure again\n",
                        table->error().to_string().c_str());
        } else if (table) {
            if (!*table) {
                return fail(table->error());
            }
            config.quality_table = table->value();
            std::printf("quality:  %zu measured settings from %s\n", config.quality_table->size(),
                        found.c_str());
        } else {
            std::printf(
                    "quality:  no measured table for this device (%s); frame budgets are "
                    "ignored until `penumbra bench accuracy` writes one\n",
                    committed.c_str());
        }
    }

    session::SessionRegistry sessions(
            limits.max_sessions,
            cluster_secret->empty() ? session::OwnerTokens()
                                    : session::OwnerTokens(*cluster_secret),
            limits.max_sessions_per_client, limits.max_sessions_per_connection);
    std::printf("access:   %s; WebSocket pages from %s\n",
                config.access_token.empty() ? "no token asked" : "token asked on /ws",
                config.allowed_origins.empty()
                        ? "this server's own origin only"
                        : ("its own origin and " + std::to_string(config.allowed_origins.size()) +
                           " listed")
                                  .c_str());
    if (!cluster_secret->empty()) {
        std::printf("cluster:  owner tokens derived from the cluster secret\n");
    }
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
