#include "arguments.hpp"
#include "commands.hpp"

#include <penumbra/net/client.hpp>
#include <penumbra/protocol/frame_header.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <thread>

namespace penumbra::app {
namespace {

using Clock = std::chrono::steady_clock;

double ms_between(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

struct Sample {
    double latency_ms = 0.0;  // request sent -> frame received, measured by the client
    double queued_ms = 0.0;
    double render_ms = 0.0;
    double readback_ms = 0.0;
    double encode_ms = 0.0;
    std::size_t bytes = 0;
};

struct Totals {
    std::mutex mutex;
    std::vector<Sample> samples;
    std::uint64_t errors = 0;
    std::vector<std::string> error_texts;
    std::uint64_t refinement_frames = 0;  // progressive refinement steps received
};

double percentile(std::vector<double> values, double q) {
    if (values.empty()) {
        return 0.0;
    }
    std::sort(values.begin(), values.end());
    const auto index = static_cast<std::size_t>(q * static_cast<double>(values.size() - 1) + 0.5);
    return values[std::min(index, values.size() - 1)];
}

// As browsers encode a query (application/x-www-form-urlencoded): letters, digits and "*-._"
// stay, a space becomes '+', every other byte %XX. A proxy hashes the volume as it is written,
// so every client must write it alike (proto/README.md §1).
std::string url_encode(const std::string& text) {
    std::string out;
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        if ((std::isalnum(byte) != 0 && byte < 0x80) || c == '*' || c == '-' || c == '.' ||
            c == '_') {
            out += c;
        } else if (c == ' ') {
            out += '+';
        } else {
            char escaped[4];
            std::snprintf(escaped, sizeof escaped, "%%%02X", byte);
            out += escaped;
        }
    }
    return out;
}

struct Options {
    std::string path;  // the WebSocket URL's path and query
    std::string host;
    unsigned short port = 0;
    std::string volume;
    std::string mode;
    int size = 512;
    std::string encoding;
    double seconds = 10.0;
    bool interactive = false;
    // > 0: jittered frames, each still refined this many times (progressive stills).
    int refine = 0;
};

// One simulated user: opens the volume, then orbits the camera and asks for a frame, waiting for
// each frame before the next request (closed loop, like a client pacing one request in flight).
void run_client(int index, const Options& o, Clock::time_point end, Totals& totals) {
    const auto fail = [&](const std::string& what) {
        const std::lock_guard lock(totals.mutex);
        ++totals.errors;
        if (totals.error_texts.size() < 5) {
            totals.error_texts.push_back("client " + std::to_string(index) + ": " + what);
        }
    };
    auto connected = net::Client::connect(o.host, o.port, o.path);
    if (!connected) {
        fail(connected.error().to_string());
        return;
    }
    net::Client& client = **connected;
    const auto expect_text = [&](const char* type) -> bool {
        while (true) {
            auto message = client.receive(std::chrono::seconds(60));
            if (!message) {
                fail(message.error().to_string());
                return false;
            }
            if (message->binary) {
                continue;
            }
            if (message->text.find(std::string("\"type\":\"") + type + "\"") != std::string::npos) {
                return true;
            }
            if (message->text.find("\"type\":\"error\"") != std::string::npos) {
                fail(message->text);
                return false;
            }
        }
    };
    if (!expect_text("hello")) {
        return;
    }
    (void)client.send_text(R"({"v":1,"type":"open","volume":")" + o.volume + "\"}");
    if (!expect_text("opened")) {
        return;
    }
    (void)client.send_text(
            R"({"v":1,"type":"set","settings":{"mode":")" + o.mode + R"(","size":[)" +
            std::to_string(o.size) + "," + std::to_string(o.size) + "]" +
            (o.refine > 0 ? R"(,"jitter":true,"refinement_steps":)" + std::to_string(o.refine)
                          : std::string()) +
            R"(},"output":{"encoding":")" + o.encoding + "\"}}");
    if (!expect_text("ack")) {
        return;
    }
    double azimuth = 17.0 * index;
    std::int64_t id = 0;
    while (Clock::now() < end) {
        azimuth += 3.0;
        (void)client.send_text(R"({"v":1,"type":"set","camera":{"orbit":{"azimuth":)" +
                               std::to_string(azimuth) + R"(,"elevation":10,"distance":2.6}}})");
        ++id;
        const Clock::time_point sent = Clock::now();
        (void)client.send_text(R"({"v":1,"type":"render","id":)" + std::to_string(id) +
                               (o.interactive ? R"(,"interactive":true})" : "}"));
        bool got_frame = false;
        while (!got_frame) {
            auto message = client.receive(std::chrono::seconds(60));
            if (!message) {
                fail(message.error().to_string());
                return;
            }
            if (!message->binary) {
                if (message->text.find("\"type\":\"error\"") != std::string::npos) {
                    fail(message->text);
                }
                continue;
            }
            const Clock::time_point received = Clock::now();
            auto frame = protocol::unpack_frame(message->bytes);
            if (!frame) {
                fail(frame.error().to_string());
                return;
            }
            if (frame->header.refinement > 0) {
                // A refinement step of an earlier still: it answers no request of this loop.
                const std::lock_guard lock(totals.mutex);
                ++totals.refinement_frames;
                continue;
            }
            if (frame->header.request != id) {
                continue;  // an earlier frame; ours is still coming
            }
            got_frame = true;
            const protocol::FrameHeader& h = frame->header;
            const std::lock_guard lock(totals.mutex);
            totals.samples.push_back({ms_between(sent, received), h.queued_ms, h.render_ms,
                                      h.readback_ms, h.encode_ms, message->bytes.size()});
        }
    }
    client.close();
}

}  // namespace

int run_load(const std::vector<std::string>& args) {
    auto parsed = Arguments::parse(args,
                                   {"host", "port", "clients", "seconds", "volume", "mode", "size",
                                    "encoding", "token-file", "refine"},
                                   {"help", "interactive"});
    if (!parsed) {
        std::fprintf(stderr, "penumbra load: %s (see --help)\n",
                     parsed.error().to_string().c_str());
        return 2;
    }
    const Arguments& a = *parsed;
    if (a.has("help")) {
        std::puts(
                "usage: penumbra load --port P [options]\n\n"
                "N simulated clients on one server, each orbiting the camera and waiting for each\n"
                "frame before asking for the next. Reports the latency from request sent to frame\n"
                "received (p50/p95/p99), its server-side split, frames/s, bytes/s and errors.\n\n"
                "  --host H          (default 127.0.0.1)\n"
                "  --port P          the server's port (required)\n"
                "  --clients N       simulated clients (default 4, at most 256)\n"
                "  --seconds T       how long to run (default 10, at most 3600)\n"
                "  --volume ID       volume id from list_volumes (default ch2.nii.gz)\n"
                "  --mode MODE       (default sbrc)\n"
                "  --size S          frames of S x S pixels (default 512)\n"
                "  --encoding E      jpeg | png (default jpeg)\n"
                "  --interactive     request interactive-quality frames\n"
                "  --refine N        jittered frames, each still refined N times at the lowest\n"
                "                    priority (progressive stills; counted apart)\n"
                "  --token-file F    the access token a server or proxy asks for\n\n"
                "The WebSocket URL names the volume (/ws?volume=ID), as a cluster's proxy routes\n"
                "by it (proto/README.md).");
        return 0;
    }
    Options o;
    o.host = a.get("host").value_or("127.0.0.1");
    o.volume = a.get("volume").value_or("ch2.nii.gz");
    o.mode = a.get("mode").value_or("sbrc");
    o.encoding = a.get("encoding").value_or("jpeg");
    o.interactive = a.has("interactive");
    const auto refine = a.integer("refine", 0);
    if (!refine || *refine < 0 || *refine > scene::kMaxRefinementSteps) {
        std::fprintf(stderr, "penumbra load: --refine takes 0..%d steps\n",
                     scene::kMaxRefinementSteps);
        return 2;
    }
    o.refine = *refine;
    o.path = "/ws?volume=" + url_encode(o.volume);
    if (const auto token_file = a.get("token-file")) {
        std::ifstream in(*token_file);
        std::string token;
        if (!in || !std::getline(in, token) || token.empty()) {
            std::fprintf(stderr, "penumbra load: --token-file: cannot read a token from '%s'\n",
                         token_file->c_str());
            return 2;
        }
        o.path += "&token=" + url_encode(token);
    }
    auto port = a.integer("port", 0);
    auto clients = a.integer("clients", 4);
    auto size = a.integer("size", 512);
    auto seconds = a.number("seconds", 10.0);
    if (!port || !clients || !size || !seconds || *port < 1 || *port > 65535 || *clients < 1 ||
        *clients > 256 || *size < 16 || *size > 8192 || *seconds <= 0.0 || *seconds > 3600.0) {
        std::fprintf(stderr,
                     "penumbra load: --port is required; --clients 1..256, --size "
                     "16..8192, --seconds (0, 3600]\n");
        return 2;
    }
    o.port = static_cast<unsigned short>(*port);
    o.size = *size;
    o.seconds = *seconds;

    Totals totals;
    const Clock::time_point start = Clock::now();
    const Clock::time_point end = start + std::chrono::duration_cast<Clock::duration>(
                                                  std::chrono::duration<double>(o.seconds));
    std::vector<std::thread> threads;
    for (int i = 0; i < *clients; ++i) {
        threads.emplace_back(run_client, i, std::cref(o), end, std::ref(totals));
    }
    for (auto& t : threads) {
        t.join();
    }
    const double elapsed = ms_between(start, Clock::now()) / 1000.0;

    std::vector<double> latency;
    std::vector<double> queued;
    std::vector<double> render;
    std::vector<double> readback;
    std::vector<double> encode;
    std::vector<double> send;
    std::size_t bytes = 0;
    for (const Sample& s : totals.samples) {
        latency.push_back(s.latency_ms);
        queued.push_back(s.queued_ms);
        render.push_back(s.render_ms);
        readback.push_back(s.readback_ms);
        encode.push_back(s.encode_ms);
        // What the server's split does not cover: the request's way in, the frame's way out.
        send.push_back(std::max(
                0.0, s.latency_ms - s.queued_ms - s.render_ms - s.readback_ms - s.encode_ms));
        bytes += s.bytes;
    }
    std::printf("load:     %d client(s), %s %dx%d %s, %.1f s against %s:%u\n", *clients,
                o.mode.c_str(), o.size, o.size, o.encoding.c_str(), elapsed, o.host.c_str(),
                o.port);
    std::printf("frames:   %zu (%.2f frames/s), %.1f KiB/frame, %.1f KiB/s, errors %llu\n",
                latency.size(), static_cast<double>(latency.size()) / elapsed,
                latency.empty()
                        ? 0.0
                        : static_cast<double>(bytes) / 1024.0 / static_cast<double>(latency.size()),
                static_cast<double>(bytes) / 1024.0 / elapsed,
                static_cast<unsigned long long>(totals.errors));
    if (o.refine > 0) {
        std::printf("refined:  %llu refinement frames besides those answering requests\n",
                    static_cast<unsigned long long>(totals.refinement_frames));
    }
    std::printf("%-22s %10s %10s %10s\n", "ms", "p50", "p95", "p99");
    const auto row = [](const char* name, const std::vector<double>& v) {
        std::printf("%-22s %10.2f %10.2f %10.2f\n", name, percentile(v, 0.50), percentile(v, 0.95),
                    percentile(v, 0.99));
    };
    row("latency (client)", latency);
    row("  queued (server)", queued);
    row("  render (server)", render);
    row("  readback (server)", readback);
    row("  encode (server)", encode);
    row("  send + network", send);
    for (const auto& text : totals.error_texts) {
        std::printf("error:    %s\n", text.c_str());
    }
    return totals.errors == 0 && !latency.empty() ? 0 : 1;
}

}  // namespace penumbra::app
