#pragma once

#include "beast.hpp"
#include "connection_handler.hpp"
#include "context.hpp"

#include <chrono>
#include <deque>
#include <memory>

namespace penumbra::net {

// One WebSocket connection: a read loop feeding the ConnectionHandler, and a bounded write queue
// in which a frame or a session state not yet being written is replaced by a newer one, so a slow
// reader only slows itself. All work runs on the connection's strand.
class WebSocketSession : public Connection, public std::enable_shared_from_this<WebSocketSession> {
public:
    WebSocketSession(tcp::socket&& socket, Context& context);
    ~WebSocketSession() override;

    // Accepts the upgrade of `client` (client_of), which holds `slot` while the connection lives.
    void run(const http::request<http::string_body>& upgrade, std::string client,
             ClientConnections::Slot slot);

    // Who the client of an upgrade on `socket` is, for per-client limits and fair shares: its
    // remote address, or what the configured proxy header says.
    [[nodiscard]] static std::string client_of(const ServerConfig& config,
                                               const http::request<http::string_body>& upgrade,
                                               const tcp::socket& socket);

    void send_text(std::string text) override;
    void send_state(std::string text) override;
    void send_frame(std::shared_ptr<const std::vector<std::uint8_t>> bytes, bool independent,
                    std::function<void()> gap) override;
    void restart_stream() override;

    void close() override;
    void defer(std::function<void()> task) override;

private:
    struct Outgoing {
        std::shared_ptr<const std::string> text;
        std::shared_ptr<const std::vector<std::uint8_t>> frame;
        bool state = false;         // a whole state, superseded by a newer one while waiting
        bool independent = true;    // a frame decodable without the ones before it
        std::function<void()> gap;  // a frame's: told when it had to be dropped
    };

    void on_accept(beast::error_code ec);
    void do_read();
    void on_read(beast::error_code ec, std::size_t bytes);
    void enqueue(Outgoing message);
    void do_write();
    void on_write(beast::error_code ec, std::size_t bytes);
    void finish();
    // Liveness: the timer checks, on the strand, when the peer was last heard from.
    void schedule_liveness_check(std::chrono::steady_clock::duration after);
    void on_liveness_check(beast::error_code ec);
    // Closes the socket without a closing handshake, which a peer that does not answer would
    // never complete; the pending read and write end, and with them the connection.
    void drop();

    websocket::stream<beast::tcp_stream> ws_;
    Context& context_;
    beast::flat_buffer buffer_;
    std::deque<Outgoing> queue_;
    bool writing_ = false;
    // A frame that needed the ones before it was dropped: frames wait for a keyframe.
    bool awaiting_keyframe_ = false;
    bool finished_ = false;
    std::string client_;
    ClientConnections::Slot slot_;
    asio::steady_timer liveness_timer_;
    std::chrono::steady_clock::time_point last_heard_;  // any message or control frame
    std::chrono::steady_clock::time_point ping_sent_;
    bool awaiting_pong_ = false;
    bool ping_in_flight_ = false;  // Beast allows one ping at a time; a slow write delays it
    std::unique_ptr<ConnectionHandler> handler_;
};

}  // namespace penumbra::net
