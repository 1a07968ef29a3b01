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
    // The session of that id, or nullptr after answering `unknown_session`.
    std::shared_ptr<session::Session> find_session(std::optional<std::int64_t> id,
                                                   const std::string& session_id);
    void send(std::string text);
    bool take_token();
    void leave_session();
    // The volume, loaded if need be, or nullptr after answering the error (at /volume).
    std::shared_ptr<const volume::Volume> acquire_volume(std::optional<std::int64_t> id,
                                                         const std::string& volume_id);
    // Makes this connection the owner of a session again: the one this server holds, or one that
    // the cluster's secret lets it re-create.
    void resume(std::optional<std::int64_t> id, const protocol::Resume& message);
    // What brings `session`'s frames, and the states its owner sets, to this connection.
    struct Sinks {
        session::ViewerSink frames;
        session::StateSink state_changed;
    };
    Sinks sinks_for(const std::shared_ptr<session::Session>& session);
    // Joins `session`'s viewers. `welcome` queues the answer (opened, joined) that must precede
    // what the sinks send.
    void watch(const std::shared_ptr<session::Session>& session, const session::StateSink& welcome);

    Context& context_;
    std::weak_ptr<Connection> connection_;
    session::ViewerId viewer_;
    std::shared_ptr<session::Session> session_;
    double tokens_;
    std::chrono::steady_clock::time_point last_refill_;
    std::uint64_t dropped_replies_ = 0;
};

}  // namespace penumbra::net
