#include "http_session.hpp"

#include "static_files.hpp"
#include "upgrade_policy.hpp"
#include "websocket_session.hpp"

#include <penumbra/base/log.hpp>
#include <penumbra/base/secret.hpp>

#include <chrono>

namespace penumbra::net {
namespace {

http::response<http::string_body> make_response(http::status status, unsigned version,
                                                bool keep_alive, std::string body,
                                                const std::string& content_type) {
    http::response<http::string_body> response{status, version};
    response.set(http::field::server, "penumbra");
    response.set(http::field::content_type, content_type);
    response.keep_alive(keep_alive);
    response.body() = std::move(body);
    response.prepare_payload();
    return response;
}

}  // namespace

HttpSession::HttpSession(tcp::socket&& socket, Context& context)
    : stream_(std::move(socket))
    , context_(context) {}

void HttpSession::run() {
    asio::dispatch(stream_.get_executor(),
                   beast::bind_front_handler(&HttpSession::do_read, shared_from_this()));
}

void HttpSession::do_read() {
    parser_.emplace();
    parser_->body_limit(64 * 1024);  // requests carry no bodies worth more
    stream_.expires_after(std::chrono::seconds(30));
    http::async_read(stream_, buffer_, *parser_,
                     beast::bind_front_handler(&HttpSession::on_read, shared_from_this()));
}

void HttpSession::on_read(beast::error_code ec, std::size_t /*bytes*/) {
    if (ec) {
        beast::error_code ignored;
        stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
        return;
    }
    http::request<http::string_body> request = parser_->release();
    const std::string target(request.target());
    const bool keep_alive = request.keep_alive();
    const unsigned version = request.version();
    const auto parsed_target = parse_request_target(target);
    if (websocket::is_upgrade(request) && parsed_target && parsed_target->path == "/ws") {
        const auto origin = request.find(http::field::origin);
        const auto checked = check_upgrade(
                {context_.config.allowed_origins, context_.config.access_token},
                origin == request.end() ? std::nullopt
                                        : std::optional<std::string_view>(origin->value()),
                request[http::field::host], *parsed_target);
        std::string client =
                WebSocketSession::client_of(context_.config, request, stream_.socket());
        ClientConnections::Slot slot;
        if (checked) {
            slot = context_.client_connections.take(client,
                                                    context_.config.max_connections_per_client);
        }
        if (slot) {
            stream_.expires_never();
            std::make_shared<WebSocketSession>(stream_.release_socket(), context_)
                    ->run(request, std::move(client), std::move(slot));
            return;
        }
        // Refused before the upgrade, with the HTTP status a browser's WebSocket reports.
        const base::Error refused =
                checked ? base::make_error(
                                  base::ErrorCode::too_many_connections,
                                  "this client (" + client + ") already holds its " +
                                          "maximum of " +
                                          std::to_string(
                                                  context_.config.max_connections_per_client) +
                                          " connections",
                                  "/ws")
                        : checked.error();
        context_.upgrades_refused.add();
        base::log_info("net", "WebSocket upgrade refused: " + refused.to_string());
        const http::status status = refused.code == base::ErrorCode::unauthorized
                                            ? http::status::unauthorized
                                    : refused.code == base::ErrorCode::too_many_connections
                                            ? http::status::too_many_requests
                                            : http::status::forbidden;
        response_ = std::make_shared<http::response<http::string_body>>(
                make_response(status, version, false, refused.message + "\n", "text/plain"));
        http::async_write(
                stream_, *response_,
                beast::bind_front_handler(&HttpSession::on_write, shared_from_this(), false));
        return;
    }
    if (request.method() != http::verb::get && request.method() != http::verb::head) {
        response_ = std::make_shared<http::response<http::string_body>>(
                make_response(http::status::method_not_allowed, version, keep_alive,
                              "only GET and HEAD\n", "text/plain"));
    } else if (target == "/healthz") {
        response_ = std::make_shared<http::response<http::string_body>>(
                make_response(http::status::ok, version, keep_alive, "ok\n", "text/plain"));
    } else if (target == "/metrics") {
        context_.sessions.set(static_cast<double>(context_.services.sessions.count()));
        context_.volume_loads.set(static_cast<double>(context_.services.volumes.loads()));
        response_ = std::make_shared<http::response<http::string_body>>(make_response(
                http::status::ok, version, keep_alive, context_.services.metrics.prometheus_text(),
                "text/plain; version=0.0.4"));
    } else if (parsed_target && parsed_target->path.starts_with(kExportsPath)) {
        response_ = std::make_shared<http::response<http::string_body>>(
                export_response(*parsed_target, version, keep_alive));
    } else if (auto file = read_static_file(context_.config.web_root, target)) {
        response_ = std::make_shared<http::response<http::string_body>>(make_response(
                http::status::ok, version, keep_alive, std::move(file->body), file->content_type));
    } else if (target == "/" || target == "/index.html") {
        response_ = std::make_shared<http::response<http::string_body>>(
                make_response(http::status::ok, version, keep_alive, built_in_index_page(),
                              "text/html; charset=utf-8"));
    } else {
        response_ = std::make_shared<http::response<http::string_body>>(make_response(
                http::status::not_found, version, keep_alive, "not found\n", "text/plain"));
    }
    if (request.method() == http::verb::head) {
        response_->body().clear();
    }
    // A large body (an export) gets time to go out at 64 KiB/s or faster.
    stream_.expires_after(std::chrono::seconds(30 + response_->body().size() / (64 * 1024)));
    http::async_write(
            stream_, *response_,
            beast::bind_front_handler(&HttpSession::on_write, shared_from_this(), keep_alive));
}

// A finished export (session::Exporter), by its id: the id is the right to it, given only to the
// connection that asked for it; with an access token the request carries that too, as the
// WebSocket's does.
http::response<http::string_body> HttpSession::export_response(const RequestTarget& target,
                                                               unsigned version, bool keep_alive) {
    const std::string& token = context_.config.access_token;
    const auto given = target.query.find("token");
    if (!token.empty() &&
        (given == target.query.end() || !base::same_secret(given->second, token))) {
        return make_response(http::status::unauthorized, version, keep_alive,
                             "this server needs its access token (?token=)\n", "text/plain");
    }
    const std::string id = target.path.substr(kExportsPath.size());
    const auto file = context_.exporter.file(id);
    if (!file) {
        return make_response(http::status::not_found, version, keep_alive,
                             "no such export: it may have expired or never finished\n",
                             "text/plain");
    }
    auto response = make_response(http::status::ok, version, keep_alive,
                                  std::string(file->bytes->begin(), file->bytes->end()),
                                  file->content_type);
    response.set(http::field::content_disposition,
                 "attachment; filename=\"" + file->file_name + "\"");
    response.set(http::field::cache_control, "no-store");
    return response;
}

void HttpSession::on_write(bool keep_alive, beast::error_code ec, std::size_t /*bytes*/) {
    if (ec) {
        return;
    }
    if (!keep_alive) {
        beast::error_code ignored;
        stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
        return;
    }
    response_.reset();
    do_read();
}

}  // namespace penumbra::net
