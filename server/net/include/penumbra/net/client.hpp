#pragma once

#include <penumbra/base/result.hpp>

#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::net {

// A blocking WebSocket client for tests, the load tool and C++ clients: one connection, one
// thread. Every call has a timeout; a timed-out connection is closed.
class Client {
public:
    // `local_address`, when not empty, is the address the connection comes from (on Linux any
    // of 127.0.0.0/8 for a loopback server: tests play several clients that way).
    static base::Result<std::unique_ptr<Client>> connect(
            const std::string& host, unsigned short port, const std::string& path = "/ws",
            std::chrono::milliseconds timeout = std::chrono::seconds(10),
            const std::string& local_address = {});

    Client(const Client&) = delete;
    Client& operator=(const Client&) = delete;
    ~Client();

    base::Status send_text(std::string_view text,
                           std::chrono::milliseconds timeout = std::chrono::seconds(10));

    base::Status send_binary(std::span<const std::uint8_t> bytes,
                             std::chrono::milliseconds timeout = std::chrono::seconds(10));

    struct Message {
        bool binary = false;
        std::string text;                 // text messages
        std::vector<std::uint8_t> bytes;  // binary messages
    };

    base::Result<Message> receive(std::chrono::milliseconds timeout = std::chrono::seconds(30));

    // Sends a close frame and waits briefly for the server's.
    void close();

    // Drops the TCP connection without a WebSocket close (a client vanishing mid-frame).
    void abort();

private:
    struct Impl;
    explicit Client(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

// A plain HTTP GET, for /healthz, /metrics and the web client's files.
struct HttpResponse {
    int status = 0;
    std::string content_type;
    std::string body;
};

base::Result<HttpResponse> http_get(const std::string& host, unsigned short port,
                                    const std::string& target,
                                    std::chrono::milliseconds timeout = std::chrono::seconds(10));

}  // namespace penumbra::net
