#include "penumbra/net/client.hpp"

#include "beast.hpp"

#include <boost/asio/connect.hpp>

namespace penumbra::net {
namespace {

base::Error network_error(const std::string& what, const beast::error_code& ec) {
    return base::make_error(
            ec == beast::error::timeout ? base::ErrorCode::timeout : base::ErrorCode::network_error,
            what + ": " + ec.message(), "client");
}

// Runs the io_context until the started operation completes (it always completes: on success,
// on error, or when the stream's deadline closes it).
void run(asio::io_context& io) {
    io.restart();
    io.run();
}

}  // namespace

struct Client::Impl {
    asio::io_context io;
    websocket::stream<beast::tcp_stream> ws{io};
    beast::flat_buffer buffer;
};

Client::Client(std::unique_ptr<Impl> impl)
    : impl_(std::move(impl)) {}

Client::~Client() {
    if (impl_ && impl_->ws.is_open()) {
        beast::error_code ignored;
        beast::get_lowest_layer(impl_->ws).socket().close(ignored);
    }
}

base::Result<std::unique_ptr<Client>> Client::connect(const std::string& host, unsigned short port,
                                                      const std::string& path,
                                                      std::chrono::milliseconds timeout,
                                                      const std::string& local_address) {
    auto impl = std::make_unique<Impl>();
    tcp::resolver resolver(impl->io);
    beast::error_code ec;
    const auto endpoints = resolver.resolve(host, std::to_string(port), ec);
    if (ec) {
        return network_error("cannot resolve " + host, ec);
    }
    auto& stream = beast::get_lowest_layer(impl->ws);
    stream.expires_after(timeout);
    if (local_address.empty()) {
        stream.async_connect(endpoints, [&](beast::error_code e, const tcp::endpoint&) { ec = e; });
    } else {
        const auto local = asio::ip::make_address(local_address, ec);
        if (!ec) {
            stream.socket().open(local.is_v4() ? tcp::v4() : tcp::v6(), ec);
        }
        if (!ec) {
            stream.socket().bind(tcp::endpoint(local, 0), ec);
        }
        if (ec) {
            return network_error("cannot bind to " + local_address, ec);
        }
        stream.async_connect(endpoints->endpoint(), [&](beast::error_code e) { ec = e; });
    }
    run(impl->io);
    if (ec) {
        return network_error("cannot connect to " + host + ":" + std::to_string(port), ec);
    }
    stream.socket().set_option(tcp::no_delay(true), ec);
    stream.expires_after(timeout);
    impl->ws.async_handshake(host + ":" + std::to_string(port), path,
                             [&](beast::error_code e) { ec = e; });
    run(impl->io);
    if (ec) {
        return network_error("WebSocket handshake failed", ec);
    }
    impl->ws.read_message_max(64 << 20);
    return std::unique_ptr<Client>(new Client(std::move(impl)));
}

base::Status Client::send_text(std::string_view text, std::chrono::milliseconds timeout) {
    beast::error_code ec;
    beast::get_lowest_layer(impl_->ws).expires_after(timeout);
    impl_->ws.text(true);
    impl_->ws.async_write(asio::buffer(text.data(), text.size()),
                          [&](beast::error_code e, std::size_t) { ec = e; });
    run(impl_->io);
    if (ec) {
        return network_error("send failed", ec);
    }
    return base::Ok{};
}

base::Status Client::send_binary(std::span<const std::uint8_t> bytes,
                                 std::chrono::milliseconds timeout) {
    beast::error_code ec;
    beast::get_lowest_layer(impl_->ws).expires_after(timeout);
    impl_->ws.binary(true);
    impl_->ws.async_write(asio::buffer(bytes.data(), bytes.size()),
                          [&](beast::error_code e, std::size_t) { ec = e; });
    run(impl_->io);
    if (ec) {
        return network_error("send failed", ec);
    }
    return base::Ok{};
}

base::Result<Client::Message> Client::receive(std::chrono::milliseconds timeout) {
    beast::error_code ec;
    impl_->buffer.clear();
    beast::get_lowest_layer(impl_->ws).expires_after(timeout);
    impl_->ws.async_read(impl_->buffer, [&](beast::error_code e, std::size_t) { ec = e; });
    run(impl_->io);
    if (ec) {
        return network_error("receive failed", ec);
    }
    Message message;
    const auto data = impl_->buffer.cdata();
    const auto* begin = static_cast<const std::uint8_t*>(data.data());
    if (impl_->ws.got_text()) {
        message.text.assign(reinterpret_cast<const char*>(begin), data.size());
    } else {
        message.binary = true;
        message.bytes.assign(begin, begin + data.size());
    }
    return message;
}

void Client::close() {
    if (!impl_->ws.is_open()) {
        return;
    }
    beast::get_lowest_layer(impl_->ws).expires_after(std::chrono::seconds(2));
    impl_->ws.async_close(websocket::close_code::normal, [](beast::error_code) {});
    run(impl_->io);
}

void Client::abort() {
    beast::error_code ignored;
    beast::get_lowest_layer(impl_->ws).socket().shutdown(tcp::socket::shutdown_both, ignored);
    beast::get_lowest_layer(impl_->ws).socket().close(ignored);
}

base::Result<HttpResponse> http_get(const std::string& host, unsigned short port,
                                    const std::string& target, std::chrono::milliseconds timeout) {
    asio::io_context io;
    tcp::resolver resolver(io);
    beast::tcp_stream stream(io);
    beast::error_code ec;
    const auto endpoints = resolver.resolve(host, std::to_string(port), ec);
    if (ec) {
        return network_error("cannot resolve " + host, ec);
    }
    stream.expires_after(timeout);
    stream.async_connect(endpoints, [&](beast::error_code e, const tcp::endpoint&) { ec = e; });
    run(io);
    if (ec) {
        return network_error("cannot connect", ec);
    }
    http::request<http::empty_body> request{http::verb::get, target, 11};
    request.set(http::field::host, host);
    request.set(http::field::user_agent, "penumbra");
    http::async_write(stream, request, [&](beast::error_code e, std::size_t) { ec = e; });
    run(io);
    if (ec) {
        return network_error("request failed", ec);
    }
    beast::flat_buffer buffer;
    http::response<http::string_body> response;
    http::async_read(stream, buffer, response, [&](beast::error_code e, std::size_t) { ec = e; });
    run(io);
    if (ec) {
        return network_error("response failed", ec);
    }
    beast::error_code ignored;
    stream.socket().shutdown(tcp::socket::shutdown_both, ignored);
    return HttpResponse{static_cast<int>(response.result_int()),
                        std::string(response[http::field::content_type]), response.body()};
}

}  // namespace penumbra::net
