#pragma once

#include "beast.hpp"
#include "context.hpp"
#include "upgrade_policy.hpp"

#include <memory>

namespace penumbra::net {

// One HTTP connection: serves the web client's files, /healthz and /metrics, and hands a
// WebSocket upgrade of /ws over to a WebSocketSession.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
public:
    HttpSession(tcp::socket&& socket, Context& context);

    void run();

private:
    void do_read();
    void on_read(beast::error_code ec, std::size_t bytes);
    void on_write(bool keep_alive, beast::error_code ec, std::size_t bytes);
    http::response<http::string_body> export_response(const RequestTarget& target, unsigned version,
                                                      bool keep_alive);

    beast::tcp_stream stream_;
    Context& context_;
    beast::flat_buffer buffer_;
    std::optional<http::request_parser<http::string_body>> parser_;
    std::shared_ptr<http::response<http::string_body>> response_;
};

}  // namespace penumbra::net
