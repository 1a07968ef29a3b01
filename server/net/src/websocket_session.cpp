#include "websocket_session.hpp"

#include "send_queue.hpp"

#include <penumbra/base/log.hpp>

#include <algorithm>

namespace penumbra::net {
namespace {

// Text replies waiting beyond this many mean the client does not read; it is disconnected.
constexpr std::size_t max_queued_text = 512;

}  // namespace

using Clock = std::chrono::steady_clock;

WebSocketSession::WebSocketSession(tcp::socket&& socket, Context& context)
    : ws_(std::move(socket))
    , context_(context)
    , liveness_timer_(ws_.get_executor()) {}

WebSocketSession::~WebSocketSession() = default;

void WebSocketSession::run(const http::request<http::string_body>& upgrade, std::string client,
                           ClientConnections::Slot slot) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.set_option(websocket::stream_base::decorator([](websocket::response_type& response) {
        response.set(http::field::server, "penumbra");
    }));
    // Messages up to the announced limit are parsed; larger ones up to this hard cap get an
    // error reply and the connection stays; beyond it Beast closes the connection (1009).
    ws_.read_message_max(
            std::max<std::size_t>(1 << 20, 4 * context_.config.limits.max_message_bytes));
    client_ = std::move(client);
    slot_ = std::move(slot);
    ws_.async_accept(upgrade,
                     beast::bind_front_handler(&WebSocketSession::on_accept, shared_from_this()));
}

std::string WebSocketSession::client_of(const ServerConfig& config,
                                        const http::request<http::string_body>& upgrade,
                                        const tcp::socket& socket) {
    const std::string& header = config.client_address_header;
    if (!header.empty()) {
        const auto found = upgrade.find(header);
        if (found != upgrade.end()) {
            // X-Forwarded-For lists the proxies after the client.
            const std::string value(found->value());
            const std::string first = value.substr(0, value.find(','));
            const auto begin = first.find_first_not_of(' ');
            if (begin != std::string::npos) {
                return first.substr(begin, first.find_last_not_of(' ') - begin + 1);
            }
        }
    }
    beast::error_code ec;
    const auto remote = socket.remote_endpoint(ec);
    return ec ? std::string("unknown") : remote.address().to_string();
}

void WebSocketSession::on_accept(beast::error_code ec) {
    if (ec) {
        base::log_warning("net", "websocket handshake failed: " + ec.message());
        return;
    }
    context_.connections.add(1.0);
    context_.track(weak_from_this());
    handler_ = std::make_unique<ConnectionHandler>(context_, weak_from_this(), client_);
    handler_->on_open();
    last_heard_ = Clock::now();
    // Runs inside the read loop, on the strand; the stream that stores it dies with `this`.
    ws_.control_callback([this](websocket::frame_type kind, beast::string_view) {
        last_heard_ = Clock::now();
        if (kind == websocket::frame_type::pong) {
            awaiting_pong_ = false;
        }
    });
    schedule_liveness_check(context_.config.ping_interval);
    do_read();
}

void WebSocketSession::schedule_liveness_check(Clock::duration after) {
    liveness_timer_.expires_after(after);
    liveness_timer_.async_wait(
            beast::bind_front_handler(&WebSocketSession::on_liveness_check, shared_from_this()));
}

void WebSocketSession::on_liveness_check(beast::error_code ec) {
    if (ec || finished_) {
        return;
    }
    const Clock::time_point now = Clock::now();
    if (awaiting_pong_ && last_heard_ < ping_sent_) {
        const Clock::time_point deadline = ping_sent_ + context_.config.ping_timeout;
        if (now >= deadline) {
            context_.connections_timed_out.add();
            base::log_info("net", "a client did not answer a ping within " +
                                          std::to_string(context_.config.ping_timeout.count()) +
                                          " ms; dropping it");
            drop();
            return;
        }
        schedule_liveness_check(deadline - now);
        return;
    }
    awaiting_pong_ = false;
    const Clock::time_point due = last_heard_ + context_.config.ping_interval;
    if (now < due) {
        schedule_liveness_check(due - now);
        return;
    }
    ping_sent_ = now;
    awaiting_pong_ = true;
    if (!ping_in_flight_) {
        ping_in_flight_ = true;
        ws_.async_ping({}, [self = shared_from_this()](beast::error_code) {
            self->ping_in_flight_ = false;
        });
    }
    schedule_liveness_check(context_.config.ping_timeout);
}

void WebSocketSession::drop() {
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().shutdown(tcp::socket::shutdown_both, ignored);
    beast::get_lowest_layer(ws_).close();
}

void WebSocketSession::do_read() {
    ws_.async_read(buffer_,
                   beast::bind_front_handler(&WebSocketSession::on_read, shared_from_this()));
}

void WebSocketSession::on_read(beast::error_code ec, std::size_t /*bytes*/) {
    if (ec) {
        if (ec != websocket::error::closed && ec != asio::error::operation_aborted &&
            ec != asio::error::eof) {
            base::log_debug("net", "websocket read ended: " + ec.message());
        }
        finish();
        return;
    }
    last_heard_ = Clock::now();
    if (ws_.got_text()) {
        const auto data = buffer_.cdata();
        handler_->on_text(std::string_view(static_cast<const char*>(data.data()), data.size()));
    } else {
        handler_->on_binary();
    }
    buffer_.consume(buffer_.size());
    do_read();
}

void WebSocketSession::finish() {
    if (finished_) {
        return;
    }
    finished_ = true;
    liveness_timer_.cancel();
    if (handler_) {
        handler_->on_close();
        context_.connections.add(-1.0);
    }
    // The queue is left alone: a write in flight still reads its front element.
}

void WebSocketSession::send_text(std::string text) {
    auto shared = std::make_shared<const std::string>(std::move(text));
    asio::post(ws_.get_executor(), [self = shared_from_this(), shared] {
        self->enqueue({shared, nullptr, false, true, {}});
    });
}

void WebSocketSession::send_state(std::string text) {
    auto shared = std::make_shared<const std::string>(std::move(text));
    asio::post(ws_.get_executor(), [self = shared_from_this(), shared] {
        self->enqueue({shared, nullptr, true, true, {}});
    });
}

void WebSocketSession::send_frame(std::shared_ptr<const std::vector<std::uint8_t>> bytes,
                                  bool independent, std::function<void()> gap) {
    asio::post(ws_.get_executor(), [self = shared_from_this(), bytes = std::move(bytes),
                                    independent, gap = std::move(gap)]() mutable {
        self->enqueue({nullptr, bytes, false, independent, std::move(gap)});
    });
}

void WebSocketSession::restart_stream() {
    asio::post(ws_.get_executor(),
               [self = shared_from_this()] { self->awaiting_keyframe_ = true; });
}

void WebSocketSession::enqueue(Outgoing message) {
    if (finished_) {
        return;
    }
    if (message.frame) {
        std::function<void()> gap = message.gap;
        const FrameAdmission admitted = admit_frame(
                queue_, writing_, std::move(message),
                static_cast<std::size_t>(std::max(1, context_.config.limits.max_send_queue)),
                awaiting_keyframe_);
        context_.frames_dropped.add(admitted.dropped);
        if (admitted.gap && gap) {
            gap();
        }
        if (!admitted.queued) {
            return;
        }
        if (admitted.dropped == 0) {
            context_.frames_sent.add();
            if (!writing_) {
                do_write();
            }
        }
        return;
    }
    if (message.state) {
        const auto first_waiting = queue_.begin() + (writing_ ? 1 : 0);
        const auto waiting_state = std::find_if(first_waiting, queue_.end(),
                                                [](const Outgoing& o) { return o.state; });
        if (waiting_state != queue_.end()) {
            // Dropped rather than overwritten in place: the newer state goes to the end, after
            // the frames and replies queued since, so the client sees them in the order they came.
            queue_.erase(waiting_state);
        }
    }
    if (!message.frame && queue_.size() >= max_queued_text) {
        base::log_warning("net", "a client stopped reading its replies; disconnecting it");
        close();
        return;
    }
    queue_.push_back(std::move(message));
    if (!writing_) {
        do_write();
    }
}

void WebSocketSession::do_write() {
    if (queue_.empty() || finished_) {
        writing_ = false;
        return;
    }
    writing_ = true;
    const Outgoing& next = queue_.front();
    if (next.text) {
        ws_.text(true);
        ws_.async_write(asio::buffer(*next.text),
                        beast::bind_front_handler(&WebSocketSession::on_write, shared_from_this()));
    } else {
        ws_.binary(true);
        ws_.async_write(asio::buffer(*next.frame),
                        beast::bind_front_handler(&WebSocketSession::on_write, shared_from_this()));
    }
}

void WebSocketSession::on_write(beast::error_code ec, std::size_t /*bytes*/) {
    if (ec) {
        finish();
        return;
    }
    if (!queue_.empty()) {
        queue_.pop_front();
    }
    do_write();
}

void WebSocketSession::defer(std::function<void()> task) {
    asio::post(ws_.get_executor(), [self = shared_from_this(), task = std::move(task)] {
        if (!self->finished_) {
            task();
        }
    });
}

void WebSocketSession::close() {
    asio::dispatch(ws_.get_executor(), [self = shared_from_this()] {
        if (self->ws_.is_open()) {
            self->ws_.async_close(websocket::close_code::going_away,
                                  [self](beast::error_code) { self->finish(); });
        }
    });
}

}  // namespace penumbra::net
