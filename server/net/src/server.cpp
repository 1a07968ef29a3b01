#include "penumbra/net/server.hpp"

#include "beast.hpp"
#include "context.hpp"
#include "http_session.hpp"

#include <penumbra/base/log.hpp>

#include <condition_variable>
#include <thread>
#include <vector>

namespace penumbra::net {

struct Server::Impl {
    asio::io_context io;
    tcp::acceptor acceptor;
    Context context;
    std::vector<std::thread> threads;
    asio::signal_set signals;
    std::mutex mutex;
    std::condition_variable stopped_signal;
    bool stopped = false;

    Impl(const ServerConfig& config, Services services, int io_threads)
        : io(io_threads)
        , acceptor(asio::make_strand(io))
        , context(config, services)
        , signals(io) {}

    void do_accept() {
        acceptor.async_accept(asio::make_strand(io), [this](beast::error_code ec, tcp::socket socket) {
            if (ec) {
                if (ec != asio::error::operation_aborted) {
                    base::log_warning("net", "accept failed: " + ec.message());
                }
                if (!acceptor.is_open()) {
                    return;
                }
            } else {
                // Small messages (a camera move, a render request) must not wait for Nagle's
                // algorithm to meet the peer's delayed ACK: that costs 40 ms a round trip.
                beast::error_code ignored;
                socket.set_option(tcp::no_delay(true), ignored);
                std::make_shared<HttpSession>(std::move(socket), context)->run();
            }
            do_accept();
        });
    }
};

Server::Server(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Server::~Server() { stop(); }

base::Result<std::unique_ptr<Server>> Server::start(const ServerConfig& config,
                                                    Services services) {
    const int io_threads = std::max(1, config.io_threads);
    auto impl = std::make_unique<Impl>(config, services, io_threads);
    beast::error_code ec;
    const auto address = asio::ip::make_address(config.address, ec);
    if (ec) {
        return base::make_error("invalid_argument", "not an IP address: " + config.address,
                                "--address");
    }
    const tcp::endpoint endpoint{address, config.port};
    impl->acceptor.open(endpoint.protocol(), ec);
    if (!ec) {
        impl->acceptor.set_option(asio::socket_base::reuse_address(true), ec);
    }
    if (!ec) {
        impl->acceptor.bind(endpoint, ec);
    }
    if (!ec) {
        impl->acceptor.listen(asio::socket_base::max_listen_connections, ec);
    }
    if (ec) {
        return base::make_error("listen_failed",
                                "cannot listen on " + config.address + ":" +
                                        std::to_string(config.port) + ": " + ec.message(),
                                "--port");
    }
    impl->do_accept();
    for (int i = 0; i < io_threads; ++i) {
        impl->threads.emplace_back([io = &impl->io] { io->run(); });
    }
    std::unique_ptr<Server> server(new Server(std::move(impl)));
    base::log_info("net", "listening on http://" + config.address + ":" +
                                  std::to_string(server->port()) + " (WebSocket at /ws)");
    return server;
}

unsigned short Server::port() const {
    beast::error_code ec;
    const auto endpoint = impl_->acceptor.local_endpoint(ec);
    return ec ? 0 : endpoint.port();
}

void Server::wait_for_shutdown_signal() {
    impl_->signals.add(SIGINT);
    impl_->signals.add(SIGTERM);
    impl_->signals.async_wait([this](beast::error_code ec, int signal) {
        if (!ec) {
            base::log_info("net", "signal " + std::to_string(signal) + ": shutting down");
            const std::lock_guard lock(impl_->mutex);
            impl_->stopped = true;
            impl_->stopped_signal.notify_all();
        }
    });
    std::unique_lock lock(impl_->mutex);
    impl_->stopped_signal.wait(lock, [&] { return impl_->stopped; });
}

void Server::stop() {
    if (!impl_ || impl_->threads.empty()) {
        return;
    }
    {
        const std::lock_guard lock(impl_->mutex);
        impl_->stopped = true;
        impl_->stopped_signal.notify_all();
    }
    asio::post(impl_->acceptor.get_executor(), [impl = impl_.get()] {
        beast::error_code ignored;
        impl->acceptor.close(ignored);
        impl->signals.cancel(ignored);
    });
    for (const auto& weak : impl_->context.tracked()) {
        if (auto connection = weak.lock()) {
            connection->close();
        }
    }
    // Let the close handshakes go out, then stop whatever is left.
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    impl_->io.stop();
    for (auto& thread : impl_->threads) {
        thread.join();
    }
    impl_->threads.clear();
}

}  // namespace penumbra::net
