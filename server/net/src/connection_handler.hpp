#pragma once

#include "context.hpp"

#include <penumbra/protocol/messages.hpp>
#include <penumbra/session/session.hpp>

#include <chrono>
#include <memory>
#include <string>
#include <string_view>

namespace penumbra::net {

// The protocol for one connection: parses each message, applies it to the session layer and
// answers. Lives on the connection's strand, so it needs no locking of its own.
class ConnectionHandler {
public:
    ConnectionHandler(Context& context, std::weak_ptr<Connection> connection);

    void on_open();
    void on_text(std::string_view text);
    void on_binary();
    // The connection is gone: leave the session; a session nobody watches is closed.
    void on_close();

private:
    void handle(const protocol::Request& request);
    void reply_error(std::optional<std::int64_t> id, const base::Error& error);
    void send(std::string text);
    bool take_token();
    void leave_session();
    // What brings `session`'s frames, and the states its owner sets, to this connection.
    struct Sinks {
        session::ViewerSink frames;
        session::StateSink state_changed;
    };
    Sinks sinks_for(const std::string& session_id);

    Context& context_;
    std::weak_ptr<Connection> connection_;
    session::ViewerId viewer_;
    std::shared_ptr<session::Session> session_;
    double tokens_;
    std::chrono::steady_clock::time_point last_refill_;
    std::uint64_t dropped_replies_ = 0;
};

}  // namespace penumbra::net
