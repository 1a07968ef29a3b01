#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/metrics/registry.hpp>
#include <penumbra/protocol/limits.hpp>
#include <penumbra/scene/default_preset.hpp>
#include <penumbra/session/scheduler.hpp>
#include <penumbra/session/session.hpp>
#include <penumbra/session/volume_store.hpp>

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace penumbra::net {

struct ServerConfig {
    std::string address = "127.0.0.1";
    unsigned short port = 8080;  // 0: any free port (see Server::port)
    int io_threads = 2;
    std::filesystem::path web_root;  // the built web client; empty: a small built-in page
    protocol::Limits limits;
    std::string default_transfer_function{scene::kDefaultPreset};
    // New sessions on a volume whose values are Hounsfield units (a CT) start from this one.
    std::string default_ct_transfer_function{scene::kDefaultHounsfieldPreset};
    // A WebSocket connection that has sent nothing for `ping_interval` is pinged; one that then
    // sends nothing, not even the pong, for `ping_timeout` is dropped. A frozen or vanished client
    // thus leaves its session (and an owner's resume works) within interval + timeout.
    std::chrono::milliseconds ping_interval = std::chrono::seconds(15);
    std::chrono::milliseconds ping_timeout = std::chrono::seconds(15);
    // Where a client's address comes from for per-client limits and fair shares: the remote
    // address of its connection, or, behind a proxy that sets it (X-Real-IP, X-Forwarded-For),
    // this request header of the WebSocket upgrade. Only for a proxy that overwrites the header:
    // clients could otherwise name themselves.
    std::string client_address_header;
    // WebSocket connections one client address (as above) may hold open at once; an upgrade
    // beyond it is refused with 429. Each connection costs a socket and its queues, whether or
    // not it opens a session, so one address must not be able to take them all.
    int max_connections_per_client = 32;
    // Who may open the WebSocket at /ws. A browser's Origin must be the server's own or one of
    // these ("*": any); clients that send no Origin (not browsers) are not concerned.
    std::vector<std::string> allowed_origins;
    // Not empty: the upgrade must carry it as the `token` query parameter (/ws?token=...).
    std::string access_token;
};

// What the server serves; owned by the caller and outliving the server.
struct Services {
    session::VolumeStore& volumes;
    session::SessionRegistry& sessions;
    session::Scheduler& scheduler;
    metrics::Registry& metrics;
};

// One port for everything: the web client and /healthz, /metrics over HTTP, and the protocol of
// proto/README.md over a WebSocket at /ws. I/O runs on `io_threads` Asio threads; each connection
// works on its own strand.
class Server {
public:
    // The limits of `config` above what the scheduler's renderer can allocate (texture size,
    // array layers) are lowered to it.
    static base::Result<std::unique_ptr<Server>> start(const ServerConfig& config,
                                                       Services services);

    Server(const Server&) = delete;
    Server& operator=(const Server&) = delete;
    ~Server();

    [[nodiscard]] unsigned short port() const;

    // Blocks until SIGINT or SIGTERM (or stop() from another thread).
    void wait_for_shutdown_signal();

    // Closes the listener and every connection, then joins the I/O threads.
    void stop();

private:
    struct Impl;
    explicit Server(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra::net
