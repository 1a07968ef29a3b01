#pragma once

#include "context.hpp"

#include <penumbra/protocol/messages.hpp>
#include <penumbra/session/session.hpp>

#include <chrono>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace penumbra::net {

// The protocol for one connection: parses each message, applies it to the session layer and
// answers. Lives on the connection's strand, so it needs no locking of its own. A request that
// reads files (open) is carried out on the volume store's loader threads; the requests that
// arrive meanwhile wait, so that replies keep the order of the requests.
class ConnectionHandler {
public:
    // `client` names who is connected (its address), for per-client limits and fair shares.
    ConnectionHandler(Context& context, std::weak_ptr<Connection> connection, std::string client);

    void on_open();
    void on_text(std::string_view text);
    void on_binary();
    // The connection is gone: leave the session; a session nobody watches is closed.
    void on_close();

private:
    // Hands the request to the handler of its message type.
    void handle(const protocol::Request& request);
    // One handler per message type of protocol::ClientMessage: a specialisation each, defined in
    // the .cpp before the dispatch; a message type without one uses this deleted template and does
    // not compile.
    template <class Message>
    void handle(std::optional<std::int64_t> id, const Message& message) = delete;

    using LoadedVolume = session::LoadedVolume;
    // Starts a load that calls its callback on a loader thread, the connection busy meanwhile, and
    // then, on the strand, hands the result to `then` and handles the requests that waited.
    template <class Loaded>
    void after_load(const std::function<void(std::function<void(Loaded)>)>& start,
                    std::function<void(const Loaded&)> then);
    // Loads `volume_id` on the volume store's loader threads, the connection busy meanwhile, and
    // then, on the strand, hands the volume (or the error) to `then` and handles the requests that
    // waited.
    void load_then(std::optional<std::int64_t> id, const std::string& volume_id,
                   std::function<void(std::optional<std::int64_t>, const LoadedVolume&)> then);
    // The second half of `open`, on the strand, once the volume is loaded (or is not).
    void finish_open(std::optional<std::int64_t> id, const std::string& volume_id,
                     const LoadedVolume& volume);
    // Join (no owner token) and resume (the owner's token) of a session this server holds: adds
    // this connection's viewer to it, or makes it the owner, welcomed with `joined` or `opened`,
    // and makes it the connection's session. Replies with the error and returns false if the
    // session refuses.
    bool enter_session(std::optional<std::int64_t> id, const std::string& session_id,
                       const std::optional<std::string>& owner_token);
    // Resumes the session this server holds.
    void resume_held(std::optional<std::int64_t> id, const protocol::Resume& message);
    // The second half of a resume that re-creates a session, once the volume is loaded.
    void finish_recreate(std::optional<std::int64_t> id, const protocol::Resume& message,
                         const LoadedVolume& volume);
    // Makes this connection the owner and first viewer of `session`, which it opened (or
    // re-created), and answers `opened`.
    void become_owner(std::optional<std::int64_t> id, std::shared_ptr<session::Session> session,
                      bool recreated);
    // Draws `labels` (listed as `volume_id`; null: none) in the connection's session and answers
    // `labels`, or the error.
    void draw_labels(std::optional<std::int64_t> id, const std::string& volume_id,
                     const std::shared_ptr<const volume::LabelMap>& labels);
    // Answers a pick in session `session_id` with what Session::pick found, or its error.
    void answer_pick(std::optional<std::int64_t> id, const std::string& session_id,
                     const protocol::Pick& message, const session::PickAnswer& picked);

    // An export's still job: the session's at width x height, and the file's name (`extension`
    // its end); nullopt, answered, where the connection is in no session or a side is no whole
    // number.
    struct ExportRequest {
        session::RenderJob still;
        std::string file_name;
    };

    std::optional<ExportRequest> export_request(std::optional<std::int64_t> id, double width,
                                                double height, std::string_view extension);
    // What brings an export's statuses to this connection, answering request `id`.
    session::Exporter::Progress export_progress(std::optional<std::int64_t> id);
    // Keeps an export that started, to cancel it when the connection closes; answers an error.
    void track_export(std::optional<std::int64_t> id, const base::Result<std::string>& started);
    // Replies with no_session and returns false if the connection is in no session.
    bool need_session(std::optional<std::int64_t> id);
    void handle_waiting();
    void reply_error(std::optional<std::int64_t> id, const base::Error& error);
    void send(std::string text);
    bool take_token();
    // Counts a message and takes a token for it; without one, answers rate_limited (while the
    // client still reads answers) and returns false.
    bool admit(std::optional<std::int64_t> id);
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
    double refusal_tokens_;  // error replies a flood may still get (connection_handler.cpp)
    std::chrono::steady_clock::time_point last_refill_;
    std::string client_;
    bool busy_ = false;                 // a request is being carried out off the strand
    std::vector<std::string> exports_;  // started by this connection, cancelled when it closes
    std::deque<protocol::Request> waiting_;
};

}  // namespace penumbra::net
