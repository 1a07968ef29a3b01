// `penumbra load` against a server over its rate limit. The server is played here, so that every
// request is refused however fast or slow frames would be (sanitizers slow them 5-20 times): the
// run must end on its time, with its errors counted as rate_limited and its requests spaced by
// the backoff schedule.

#include <penumbra/net/load.hpp>
#include <penumbra/protocol/messages.hpp>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdint>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace penumbra::integration {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

// A server over its rate limit, on 127.0.0.1 and a free port: it greets, refuses the first
// `refused_setup` `open` messages and as many first `set` messages (the session's settings) with
// rate_limited, opens and acknowledges the next as penumbra's server does, then refuses every
// message
// with rate_limited (a request's refusal carries its id) and, after `answered_refusals`
// refusals on a connection, answers nothing more there, as penumbra's server stops answering a
// client that keeps sending into its limit. It notes when each render and each set arrived.
class RateLimitedServer {
public:
    explicit RateLimitedServer(int answered_refusals, int refused_setup = 0)
        : answered_refusals_(answered_refusals)
        , refused_setup_(refused_setup)
        , acceptor_(io_, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0))
        , port_(acceptor_.local_endpoint().port()) {
        accept();
        thread_ = std::thread([this] { io_.run(); });
    }

    RateLimitedServer(const RateLimitedServer&) = delete;
    RateLimitedServer& operator=(const RateLimitedServer&) = delete;

    ~RateLimitedServer() {
        io_.stop();
        thread_.join();
    }

    [[nodiscard]] unsigned short port() const { return port_; }

    // Drops every connection: a client still waiting for an answer then fails.
    void drop_connections() {
        asio::post(io_, [this] {
            acceptor_.close();
            for (const auto& weak : connections_) {
                if (const auto connection = weak.lock()) {
                    beast::error_code ignored;
                    beast::get_lowest_layer(connection->ws).socket().close(ignored);
                }
            }
        });
    }

    // When each render arrived, per connection.
    [[nodiscard]] std::vector<std::vector<Clock::time_point>> renders() const {
        const std::lock_guard lock(mutex_);
        return renders_;
    }

    // When each open arrived, per connection.
    [[nodiscard]] std::vector<std::vector<Clock::time_point>> opens() const {
        const std::lock_guard lock(mutex_);
        return opens_;
    }

    // When each set arrived before the session's settings were acknowledged, per connection.
    [[nodiscard]] std::vector<std::vector<Clock::time_point>> sets() const {
        const std::lock_guard lock(mutex_);
        return sets_;
    }

private:
    struct Connection {
        explicit Connection(tcp::socket socket)
            : ws(std::move(socket)) {}

        websocket::stream<beast::tcp_stream> ws;
        beast::flat_buffer buffer;
        std::string reply;
        bool session_set = false;
        int refused_opens = 0;
        int refused_sets = 0;
        int refusals = 0;
        std::size_t index = 0;  // into renders_
    };

    using Shared = std::shared_ptr<Connection>;

    void accept() {
        acceptor_.async_accept([this](beast::error_code ec, tcp::socket socket) {
            if (ec) {
                return;
            }
            // As penumbra's server: a reply leaves at once, not held back for the next one.
            socket.set_option(tcp::no_delay(true), ec);
            auto connection = std::make_shared<Connection>(std::move(socket));
            {
                const std::lock_guard lock(mutex_);
                connection->index = renders_.size();
                renders_.emplace_back();
                opens_.emplace_back();
                sets_.emplace_back();
            }
            connections_.push_back(connection);
            connection->ws.async_accept([this, connection](beast::error_code error) {
                if (!error) {
                    write(connection, R"({"v":1,"type":"hello"})");
                }
            });
            accept();
        });
    }

    void write(const Shared& connection, std::string text) {
        connection->reply = std::move(text);
        connection->ws.text(true);
        connection->ws.async_write(asio::buffer(connection->reply),
                                   [this, connection](beast::error_code ec, std::size_t) {
                                       if (!ec) {
                                           read(connection);
                                       }
                                   });
    }

    void read(const Shared& connection) {
        connection->ws.async_read(connection->buffer,
                                  [this, connection](beast::error_code ec, std::size_t) {
                                      if (!ec) {
                                          answer(connection);
                                      }
                                  });
    }

    void answer(const Shared& connection) {
        const auto request =
                nlohmann::json::parse(beast::buffers_to_string(connection->buffer.data()));
        connection->buffer.consume(connection->buffer.size());
        const std::string type = request.value("type", "");
        const auto id = request.contains("id")
                                ? std::optional<std::int64_t>(request.at("id").get<std::int64_t>())
                                : std::nullopt;
        if (type == "open") {
            {
                const std::lock_guard lock(mutex_);
                opens_[connection->index].push_back(Clock::now());
            }
            if (connection->refused_opens < refused_setup_) {
                ++connection->refused_opens;
                refuse(connection, id);
                return;
            }
            write(connection, R"({"v":1,"type":"opened"})");
            return;
        }
        if (type == "set" && !connection->session_set) {
            {
                const std::lock_guard lock(mutex_);
                sets_[connection->index].push_back(Clock::now());
            }
            if (connection->refused_sets < refused_setup_) {
                ++connection->refused_sets;
                refuse(connection, id);
                return;
            }
            connection->session_set = true;
            write(connection, protocol::ack_message(id, "set"));
            return;
        }
        if (type == "render") {
            const std::lock_guard lock(mutex_);
            renders_[connection->index].push_back(Clock::now());
        }
        if (connection->refusals >= answered_refusals_) {
            read(connection);
            return;
        }
        ++connection->refusals;
        refuse(connection, id);
    }

    void refuse(const Shared& connection, std::optional<std::int64_t> id) {
        write(connection, protocol::error_message(
                                  id, base::make_error(base::ErrorCode::rate_limited,
                                                       "more than 2 requests per second", "/")));
    }

    const int answered_refusals_;
    const int refused_setup_;
    asio::io_context io_;
    tcp::acceptor acceptor_;
    const unsigned short port_;
    std::vector<std::weak_ptr<Connection>> connections_;  // on io_'s thread only
    mutable std::mutex mutex_;
    std::vector<std::vector<Clock::time_point>> renders_;
    std::vector<std::vector<Clock::time_point>> opens_;
    std::vector<std::vector<Clock::time_point>> sets_;
    std::thread thread_;
};

// Over the rate limit every render is refused by its id: each client counts the refusal as the
// answer and waits rate_limited_backoff before asking again, so it never sends into the server's
// silence, and its run ends on time instead of waiting out the reply timeout (60 s).
TEST(LoadClient, BacksOffOverTheRateLimitAndEndsOnTime) {
    // The refusals a client could reach in the run without backing off, and many more than it
    // reaches with (two messages per request).
    RateLimitedServer server(64);
    net::LoadConfig config;
    config.port = server.port();
    config.clients = 2;
    config.seconds = 4.0;
    config.volume = "ch2.nii.gz";
    config.size = 32;
    const Clock::time_point started = Clock::now();
    auto run = std::async(std::launch::async, [&config] { return net::run_load(config); });
    // The run ends on its time; a client waiting for an answer that never comes is cut off here
    // (long before its own 60 s), so that the test ends either way.
    const auto bound = std::chrono::duration<double>(config.seconds) + 10s;
    if (run.wait_for(bound) != std::future_status::ready) {
        server.drop_connections();
    }
    const net::LoadReport report = run.get();
    const std::chrono::duration<double> elapsed = Clock::now() - started;
    EXPECT_LT(elapsed.count(), config.seconds + 5.0)
            << "a client waited for an answer the server never sent";

    EXPECT_TRUE(report.samples.empty());
    EXPECT_GE(report.errors, static_cast<std::uint64_t>(config.clients));
    ASSERT_FALSE(report.error_texts.empty());
    for (const std::string& text : report.error_texts) {
        EXPECT_NE(text.find("rate_limited"), std::string::npos) << text;
    }

    // Requests no closer than the backoff schedule: as many as it fits into the run at most, and
    // each after the wait that its refusals in a row call for.
    int most_requests = 0;
    for (auto schedule = Clock::duration::zero();
         schedule < std::chrono::duration<double>(config.seconds);
         schedule += net::rate_limited_backoff(most_requests)) {
        ++most_requests;
    }
    const auto renders = server.renders();
    ASSERT_EQ(renders.size(), static_cast<std::size_t>(config.clients));
    for (const auto& arrivals : renders) {
        ASSERT_FALSE(arrivals.empty());
        EXPECT_LE(arrivals.size(), static_cast<std::size_t>(most_requests));
        for (std::size_t i = 1; i < arrivals.size(); ++i) {
            EXPECT_GE(arrivals[i] - arrivals[i - 1], net::rate_limited_backoff(static_cast<int>(i)))
                    << "request " << i + 1 << " came too early after its refusal";
        }
    }
}

// A session's open and first `set` refused over the rate limit are asked again after the backoff,
// as a render is, and the client goes on to render once they are answered.
TEST(LoadClient, RetriesARateLimitedOpenAndFirstSetAfterTheBackoff) {
    constexpr int refused = 2;
    RateLimitedServer server(64, refused);
    net::LoadConfig config;
    config.port = server.port();
    config.clients = 2;
    config.seconds = 3.0;
    config.size = 32;
    auto run = std::async(std::launch::async, [&config] { return net::run_load(config); });
    if (run.wait_for(std::chrono::duration<double>(config.seconds) + 10s) !=
        std::future_status::ready) {
        server.drop_connections();
    }
    const net::LoadReport report = run.get();
    ASSERT_FALSE(report.error_texts.empty());
    for (const std::string& text : report.error_texts) {
        EXPECT_NE(text.find("rate_limited"), std::string::npos) << text;
    }

    const auto renders = server.renders();
    ASSERT_EQ(renders.size(), static_cast<std::size_t>(config.clients));
    for (const auto& [what, arrivals] :
         {std::pair{"open", server.opens()}, {"set", server.sets()}}) {
        for (std::size_t c = 0; c < arrivals.size(); ++c) {
            SCOPED_TRACE(std::string(what) + " of client " + std::to_string(c));
            ASSERT_EQ(arrivals[c].size(), static_cast<std::size_t>(refused + 1));
            for (std::size_t i = 1; i < arrivals[c].size(); ++i) {
                EXPECT_GE(arrivals[c][i] - arrivals[c][i - 1],
                          net::rate_limited_backoff(static_cast<int>(i)))
                        << "attempt " << i + 1 << " came too early after its refusal";
            }
        }
    }
    for (std::size_t c = 0; c < renders.size(); ++c) {
        EXPECT_FALSE(renders[c].empty()) << "client " << c << " gave up before rendering";
    }
}

TEST(LoadClient, BacksOffLongerAfterEachRefusalInARowUpToFourSeconds) {
    EXPECT_EQ(net::rate_limited_backoff(1), 250ms);
    EXPECT_EQ(net::rate_limited_backoff(2), 500ms);
    EXPECT_EQ(net::rate_limited_backoff(3), 1000ms);
    EXPECT_EQ(net::rate_limited_backoff(5), 4000ms);
    EXPECT_EQ(net::rate_limited_backoff(1000), 4000ms);
}

}  // namespace
}  // namespace penumbra::integration
