#include "arguments.hpp"
#include "commands.hpp"

#include <penumbra/base/log.hpp>
#include <penumbra/metrics/registry.hpp>
#include <penumbra/net/server.hpp>
#include <penumbra/protocol/scene_json.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/session/scheduler.hpp>
#include <penumbra/session/session.hpp>
#include <penumbra/session/volume_store.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace penumbra::app {
namespace {

int fail(const base::Error& error) {
    std::fprintf(stderr, "penumbra serve: %s\n", error.to_string().c_str());
    return 1;
}

// The built web client: next to the source tree's client_web, when it has been built.
std::filesystem::path default_web_root() {
    const std::filesystem::path built = std::filesystem::path(PENUMBRA_SOURCE_DIR) / "client_web" /
                                        "dist";
    return std::filesystem::exists(built / "index.html") ? built : std::filesystem::path();
}

}  // namespace

int run_serve(const std::vector<std::string>& args) {
    auto parsed = Arguments::parse(
            args,
            {"data", "port", "address", "web-root", "io-threads", "encode-threads",
             "max-sessions", "max-image-side", "max-slices", "max-light-res",
             "max-message-bytes", "max-requests-per-second", "volume-memory-mb", "gpu-memory-mb",
             "default-tf", "quality-table"},
            {"help", "debug-gl"});
    if (!parsed) {
        std::fprintf(stderr, "penumbra serve: %s (see --help)\n",
                     parsed.error().to_string().c_str());
        return 2;
    }
    const Arguments& a = *parsed;
    if (a.has("help")) {
        std::puts(
                "usage: penumbra serve [options]\n\n"
                "  --data DIR                 folder of volumes to offer (default: Debian's\n"
                "                             /usr/share/mricron/templates)\n"
                "  --port P                   TCP port (default 8080; 0 = any free port)\n"
                "  --address A                listen address (default 127.0.0.1)\n"
                "  --web-root DIR             the built web client (default client_web/dist)\n"
                "  --io-threads N             network threads (default 2)\n"
                "  --encode-threads N         JPEG/PNG encoder threads (default 2)\n"
                "  --max-sessions N           (default 64)\n"
                "  --max-image-side N         (default 2048)\n"
                "  --max-slices N             (default 1024)\n"
                "  --max-light-res N          (default 1024)\n"
                "  --max-message-bytes N      (default 65536)\n"
                "  --max-requests-per-second R  per connection (default 120)\n"
                "  --volume-memory-mb M       loaded volumes kept in memory (default 4096)\n"
                "  --gpu-memory-mb M          volume textures kept on the GPU (default 2048)\n"
                "  --default-tf PRESET        transfer function of new sessions (mri_skin)\n"
                "  --quality-table FILE       `bench accuracy` table for sessions that set a frame\n"
                "                             budget (default docs/accuracy/llvmpipe.json on\n"
                "                             llvmpipe, docs/accuracy/gpu.json elsewhere)\n"
                "  --debug-gl                 GL debug output to the log\n"
                "\nThe address prints on start; SIGINT or SIGTERM shuts down cleanly.");
        return 0;
    }
    net::ServerConfig config;
    config.address = a.get("address").value_or("127.0.0.1");
    config.web_root = a.get("web-root").value_or(default_web_root().string());
    config.default_transfer_function = a.get("default-tf").value_or("mri_skin");
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
    int gpu_memory_mb = 2048;
    int max_message_bytes = static_cast<int>(limits.max_message_bytes);
    const IntegerOption integers[] = {
            {"port", &port, 0, 65535},
            {"io-threads", &config.io_threads, 1, 64},
            {"encode-threads", &encode_threads, 1, 64},
            {"max-sessions", &limits.max_sessions, 1, 100000},
            {"max-image-side", &limits.max_image_side, 16, 16384},
            {"max-slices", &limits.max_slices, 1, 16384},
            {"max-light-res", &limits.max_light_resolution, 1, 16384},
            {"max-message-bytes", &max_message_bytes, 1024, 16 << 20},
            {"volume-memory-mb", &volume_memory_mb, 1, 1 << 20},
            {"gpu-memory-mb", &gpu_memory_mb, 1, 1 << 20},
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

    const std::string data = a.get("data").value_or("/usr/share/mricron/templates");
    session::VolumeStore volumes(data, static_cast<std::size_t>(volume_memory_mb) << 20);
    if (auto status = volumes.scan(); !status) {
        return fail(status.error());
    }
    std::printf("data:     %s (%zu volumes)\n", data.c_str(), volumes.list().size());

    metrics::Registry registry;
    const bool debug_gl = a.has("debug-gl");
    const std::size_t gpu_budget = static_cast<std::size_t>(gpu_memory_mb) << 20;
    auto scheduler = session::Scheduler::create(
            [debug_gl, gpu_budget]() -> base::Result<std::unique_ptr<render::FrameRenderer>> {
                auto renderer = render::Renderer::create(
                        {.shader_dir = {}, .debug_context = debug_gl,
                         .volume_memory_budget = gpu_budget});
                if (!renderer) {
                    return renderer.error();
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

    const std::filesystem::path table_path =
            a.get("quality-table")
                    .value_or((std::filesystem::path(PENUMBRA_SOURCE_DIR) / "docs" / "accuracy" /
                               (info.gpu_timer_queries ? "gpu.json" : "llvmpipe.json"))
                                      .string());
    if (std::ifstream in(table_path); in) {
        std::stringstream text;
        text << in.rdbuf();
        auto table = protocol::parse_quality_table(text.str(), table_path.string());
        if (!table) {
            return fail(table.error());
        }
        config.quality_table =
                std::make_shared<const std::vector<scene::QualitySample>>(std::move(table.value()));
        std::printf("quality:  %zu measured settings from %s\n", config.quality_table->size(),
                    table_path.c_str());
    } else if (a.has("quality-table")) {
        return fail(base::make_error("not_found", "cannot read the quality table",
                                     table_path.string()));
    } else {
        std::printf("quality:  no measured table for this device (%s); frame budgets are "
                    "ignored until `penumbra bench accuracy` writes one\n",
                    table_path.c_str());
    }

    session::SessionRegistry sessions(limits.max_sessions);
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
