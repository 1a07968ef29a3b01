#include "penumbra/net/server.hpp"

#include "beast.hpp"
#include "context.hpp"
#include "http_session.hpp"

#include <penumbra/base/log.hpp>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <thread>
#include <vector>

namespace penumbra::net {

struct Server::Impl {
    // Declared before the io_context, so destroyed after it: handlers that the io_context
    // abandons when it is destroyed still hold connections, whose destructors give back their
    // per-client slots to the context.
    Context context;
    asio::io_context io;
    tcp::acceptor acceptor;
    std::vector<std::thread> threads;
    asio::signal_set signals;
    std::mutex mutex;
    std::condition_variable stopped_signal;
    bool stopped = false;

    Impl(const ServerConfig& config, Services services, int io_threads)
        : context(config, services)
        , io(io_threads)
        , acceptor(asio::make_strand(io))
        , signals(io)
        , accept_timer(acceptor.get_executor())
        , accept_failures(services.metrics.counter(
                  "penumbra_accept_failures_total",
                  "Connections the listener could not accept (out of descriptors or memory)")) {}

    void do_accept() {
        acceptor.async_accept(asio::make_strand(io),
                              [this](beast::error_code ec, tcp::socket socket) {
                                  if (ec == asio::error::operation_aborted || !acceptor.is_open()) {
                                      return;
                                  }
                                  if (ec) {
                                      // Out of descriptors (EMFILE, ENFILE) or memory, the pending
                                      // connection stays in the backlog and accepting again at once
                                      // fails again at once: wait, longer each time, so that the
                                      // loop neither spins nor floods the log.
                                      on_accept_failed(ec);
                                      return;
                                  }
                                  accept_delay = std::chrono::milliseconds(0);
                                  // Small messages (a camera move, a render request) must not wait
                                  // for Nagle's algorithm to meet the peer's delayed ACK: that
                                  // costs 40 ms a round trip.
                                  beast::error_code ignored;
                                  socket.set_option(tcp::no_delay(true), ignored);
                                  std::make_shared<HttpSession>(std::move(socket), context)->run();
                                  do_accept();
                              });
    }

    void on_accept_failed(const beast::error_code& ec) {
        using std::chrono::milliseconds;
        accept_delay = std::clamp(accept_delay * 2, min_accept_delay, max_accept_delay);
        accept_failures.add();
        ++failures_since_logged;
        const auto now = std::chrono::steady_clock::now();
        if (now >= next_failure_log) {
            base::log_warning("net", "accept failed: " + ec.message() + " (" +
                                             std::to_string(failures_since_logged) +
                                             " failures since the last report); retrying in " +
                                             std::to_string(accept_delay.count()) + " ms");
            failures_since_logged = 0;
            next_failure_log = now + failure_log_interval;
        }
        accept_timer.expires_after(accept_delay);
        accept_timer.async_wait([this](beast::error_code timer_ec) {
            if (!timer_ec && acceptor.is_open()) {
                do_accept();
            }
        });
    }

    static constexpr std::chrono::milliseconds min_accept_delay{50};
    static constexpr std::chrono::milliseconds max_accept_delay{500};
    static constexpr std::chrono::seconds failure_log_interval{10};
    asio::steady_timer accept_timer;
    std::chrono::milliseconds accept_delay{0};
    metrics::Counter& accept_failures;
    std::uint64_t failures_since_logged = 0;
    std::chrono::steady_clock::time_point next_failure_log{};
};

Server::Server(std::unique_ptr<Impl> impl)
    : impl_(std::move(impl)) {}

Server::~Server() {
    stop();
}

namespace {

// What `hello` announces, and requests are held to, never exceeds what the renderer can allocate:
// an image side or light-buffer resolution over its largest texture, more light slices than its
// array layers.
ServerConfig within_device(ServerConfig config, const session::Device& device) {
    protocol::Limits& limits = config.limits;
    limits.max_slices = std::min(limits.max_slices, device.max_array_texture_layers);
    limits.max_light_resolution = std::min(limits.max_light_resolution, device.max_texture_size);
    limits.max_image_side = std::min(limits.max_image_side, device.max_texture_size);
    return config;
}

}  // namespace

base::Result<std::unique_ptr<Server>> Server::start(const ServerConfig& requested,
                                                    Services services) {
    const ServerConfig config = within_device(requested, services.scheduler.device());
    const int io_threads = std::max(1, config.io_threads);
    auto impl = std::make_unique<Impl>(config, services, io_threads);
    beast::error_code ec;
    const auto address = asio::ip::make_address(config.address, ec);
    if (ec) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "not an IP address: " + config.address, "--address");
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
        return base::make_error(base::ErrorCode::listen_failed,
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
    {
        const std::lock_guard lock(impl_->context.lifeline->mutex);
        impl_->context.lifeline->open = false;
    }
    // Exports report to connections through the I/O threads: they end while those run.
    impl_->context.exporter.shutdown();
    asio::post(impl_->acceptor.get_executor(), [impl = impl_.get()] {
        beast::error_code ignored;
        impl->acceptor.close(ignored);
        impl->accept_timer.cancel();
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
