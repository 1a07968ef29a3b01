#pragma once

#include <penumbra/metrics/registry.hpp>
#include <penumbra/net/server.hpp>
#include <penumbra/session/exporter.hpp>

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::net {

class Connection;

// Whether the server still runs its I/O: work finishing on another thread (a volume load) hands
// its result to a connection only while it is open, so nothing is posted to an I/O context that
// is going away. Server::stop closes it.
struct Lifeline {
    std::mutex mutex;
    bool open = true;
};

// WebSocket connections open per client address. A slot counts one connection for as long as it
// lives.
class ClientConnections {
public:
    using Slot = std::shared_ptr<const std::string>;

    // A slot for one more connection of `client`, or null when it holds `maximum` already.
    Slot take(const std::string& client, int maximum) {
        const std::lock_guard lock(mutex_);
        int& open = open_[client];
        if (open >= maximum) {
            return nullptr;
        }
        ++open;
        return {new std::string(client), [this](const std::string* released) {
                    give_back(*released);
                    delete released;
                }};
    }

    [[nodiscard]] int open(const std::string& client) const {
        const std::lock_guard lock(mutex_);
        const auto found = open_.find(client);
        return found == open_.end() ? 0 : found->second;
    }

private:
    void give_back(const std::string& client) {
        const std::lock_guard lock(mutex_);
        const auto found = open_.find(client);
        if (found != open_.end() && --found->second <= 0) {
            open_.erase(found);
        }
    }

    mutable std::mutex mutex_;
    std::map<std::string, int> open_;
};

// What every connection of one server shares.
// Where a finished export is downloaded: this followed by its id.
inline constexpr std::string_view kExportsPath = "/exports/";

// What the server's exports are held to: their size by its limits, the rest by default.
inline session::ExportLimits export_limits(const protocol::Limits& limits) {
    session::ExportLimits exports;
    exports.max_side = limits.max_export_side;
    exports.max_movie_side = limits.max_movie_side;
    exports.max_movie_frames = limits.max_movie_frames;
    return exports;
}

struct Context {
    ServerConfig config;
    Services services;
    std::atomic<std::uint64_t> next_viewer{1};
    std::shared_ptr<Lifeline> lifeline = std::make_shared<Lifeline>();
    ClientConnections client_connections;
    metrics::Gauge& connections;
    metrics::Counter& messages;
    metrics::Counter& errors;
    metrics::Counter& frames_sent;
    metrics::Counter& frames_dropped;
    metrics::Histogram& frame_server_ms;
    metrics::Gauge& sessions;
    metrics::Counter& connections_timed_out;
    metrics::Counter& upgrades_refused;
    metrics::Gauge& volume_loads;

    Context(ServerConfig c, Services s)
        : config(std::move(c))
        , services(s)
        , connections(s.metrics.gauge("penumbra_connections", "Open WebSocket connections"))
        , messages(s.metrics.counter("penumbra_messages_total", "Protocol messages received"))
        , errors(s.metrics.counter("penumbra_errors_total", "Error messages sent to clients"))
        , frames_sent(s.metrics.counter("penumbra_frames_sent_total", "Frames sent to viewers"))
        , frames_dropped(s.metrics.counter(
                  "penumbra_frames_dropped_total",
                  "Frames not sent because a newer one replaced them in a slow client's queue"))
        , frame_server_ms(s.metrics.histogram(
                  "penumbra_frame_server_ms",
                  "Server time per frame: queued + render + readback + encode (ms)",
                  metrics::latency_buckets_ms()))
        , sessions(s.metrics.gauge("penumbra_sessions", "Open sessions"))
        , connections_timed_out(s.metrics.counter(
                  "penumbra_connections_timed_out_total",
                  "WebSocket connections dropped for not answering a ping in time"))
        , upgrades_refused(s.metrics.counter(
                  "penumbra_upgrades_refused_total",
                  "WebSocket upgrades refused for their Origin, a missing or wrong token, or "
                  "too many connections of their client"))
        , volume_loads(s.metrics.gauge("penumbra_volume_loads",
                                       "Volume files read since the server started (a cluster "
                                       "that routes by volume reads each once)"))
        , exporter(s.scheduler, export_limits(config.limits)) {}

    // Open connections, so that shutdown can close them.
    void track(std::weak_ptr<Connection> connection) {
        const std::lock_guard lock(connections_mutex);
        std::erase_if(open_connections, [](const auto& c) { return c.expired(); });
        open_connections.push_back(std::move(connection));
    }

    std::vector<std::weak_ptr<Connection>> tracked() {
        const std::lock_guard lock(connections_mutex);
        return open_connections;
    }

    std::mutex connections_mutex;
    std::vector<std::weak_ptr<Connection>> open_connections;

    // Its exports end in Server::stop, while the I/O threads still run; last, so that it goes
    // first in any case.
    session::Exporter exporter;
};

// The sending side of a WebSocket connection. Both calls are thread-safe and never block: they
// queue the message for the connection's strand.
class Connection {
public:
    virtual ~Connection() = default;

    virtual void send_text(std::string text) = 0;

    // A text that carries a whole session state: one still waiting to be written is dropped for
    // the newer, which goes to the end of the queue. A slow reader thus gets the latest state
    // without a backlog of the steps in between.
    virtual void send_state(std::string text) = 0;

    // A frame may be dropped while the client is slow, as its stream allows: an `independent`
    // frame (every JPEG or PNG frame, an H.264 keyframe) takes the place of the frames still
    // waiting; a frame that needs the ones before it waits behind them, and where too many wait
    // it is dropped, `gap` is called, and the frames after it are dropped until an independent
    // one comes (which `gap` asks the session for).
    virtual void send_frame(std::shared_ptr<const std::vector<std::uint8_t>> bytes,
                            bool independent, std::function<void()> gap) = 0;

    // The frames sent after this call start a stream anew (the connection enters a session): until
    // an independent frame comes, a frame that needs the ones before it is dropped.
    virtual void restart_stream() = 0;

    // Closes the connection politely (server shutdown, or a client that stopped reading).
    virtual void close() = 0;

    // Runs `task` on the connection's strand, unless the connection has ended by then.
    virtual void defer(std::function<void()> task) = 0;
};

}  // namespace penumbra::net
