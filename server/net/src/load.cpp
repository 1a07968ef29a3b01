#include "penumbra/net/load.hpp"

#include <penumbra/net/client.hpp>
#include <penumbra/protocol/frame_header.hpp>
#include <penumbra/protocol/messages.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

namespace penumbra::net {
namespace {

using Clock = std::chrono::steady_clock;

constexpr auto reply_timeout = std::chrono::seconds(60);
constexpr std::size_t kept_error_texts = 5;

double ms_between(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

double percentile(std::vector<double> values, double q) {
    if (values.empty()) {
        return 0.0;
    }
    std::sort(values.begin(), values.end());
    const auto index =
            static_cast<std::size_t>(std::lround(q * static_cast<double>(values.size() - 1)));
    return values[std::min(index, values.size() - 1)];
}

// As browsers encode a query (application/x-www-form-urlencoded): letters, digits and "*-._"
// stay, a space becomes '+', every other byte %XX.
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

// What the clients share: the report they add to, under its lock.
class SharedReport {
public:
    void fail(int client, const std::string& what) {
        const std::lock_guard lock(mutex_);
        ++report_.errors;
        if (report_.error_texts.size() < kept_error_texts) {
            report_.error_texts.push_back("client " + std::to_string(client) + ": " + what);
        }
    }

    void add(const LoadSample& sample) {
        const std::lock_guard lock(mutex_);
        report_.samples.push_back(sample);
    }

    void add_refinement_frame() {
        const std::lock_guard lock(mutex_);
        ++report_.refinement_frames;
    }

    LoadReport take() {
        const std::lock_guard lock(mutex_);
        return std::move(report_);
    }

private:
    std::mutex mutex_;
    LoadReport report_;
};

std::string settings_message(const LoadConfig& config, std::int64_t id) {
    const std::string size = std::to_string(config.size);
    // Exactly `refine` steps, however little the last ones change the image: the load asked for
    // is the one measured.
    const std::string refine =
            (config.refine > 0 ? R"(,"jitter":true,"refinement_threshold":0)" : "") +
            std::string(R"(,"refinement_steps":)") + std::to_string(config.refine);
    const std::string output = config.encoding.empty()
                                       ? std::string()
                                       : R"(,"output":{"encoding":")" + config.encoding + "\"}";
    return R"({"v":1,"type":"set","id":)" + std::to_string(id) + R"(,"settings":{"mode":")" +
           config.mode + R"(","size":[)" + size + "," + size + "]" + refine + "}" + output + "}";
}

// One simulated user: opens the volume, then orbits the camera and asks for a frame, waiting for
// each frame before the next request.
class LoadClient {
public:
    LoadClient(int index, const LoadConfig& config, SharedReport& report)
        : index_(index)
        , config_(config)
        , report_(report) {}

    void run(Clock::time_point end) {
        auto connected = Client::connect(config_.host, config_.port,
                                         load_path(config_.volume, config_.token));
        if (!connected) {
            report_.fail(index_, connected.error().to_string());
            return;
        }
        client_ = std::move(connected.value());
        end_ = end;
        if (!open_session()) {
            return;
        }
        // At least one frame each: on a loaded server the open alone may outlast a short run, and
        // a run that measured no frame would say nothing about the latency it was asked for.
        double azimuth = 17.0 * index_;
        do {
            azimuth += 3.0;
            if (!request_frame(azimuth, ++last_id_)) {
                return;
            }
        } while (Clock::now() < end);
        client_->close();
    }

private:
    // hello, open the volume, set the frame's settings; false where one failed (reported) or the
    // run ended first. The open and the settings are asked again after a rate_limited refusal, as
    // a render is: a server that refused them would otherwise lose the client for the whole run.
    bool open_session() {
        if (expect_text("hello") != Reply::expected) {
            return false;
        }
        return ask_until_answered(
                       [this] {
                           return R"({"v":1,"type":"open","id":)" + std::to_string(++last_id_) +
                                  R"(,"volume":")" + config_.volume + "\"}";
                       },
                       "opened") &&
               ask_until_answered([this] { return settings_message(config_, ++last_id_); }, "ack");
    }

    // Sends the message `make` writes until the answer of `type` comes, backing off after each
    // rate_limited refusal; false on another error, no answer, or the run's end.
    template <class Make>
    bool ask_until_answered(Make make, const char* type) {
        while (true) {
            (void)client_->send_text(make());
            switch (expect_text(type)) {
                case Reply::expected:
                    refusals_ = 0;
                    return true;
                case Reply::failed:
                    return false;
                case Reply::rate_limited:
                    back_off();
                    if (Clock::now() >= end_) {
                        return false;
                    }
                    break;
            }
        }
    }

    enum class Reply { expected, rate_limited, failed };

    // Skips frames up to the text message of `type`; an error message (reported) or none is not
    // it, and a rate_limited error says so, since a later attempt may pass.
    Reply expect_text(const char* type) {
        while (true) {
            auto message = client_->receive(reply_timeout);
            if (!message) {
                report_.fail(index_, message.error().to_string());
                return Reply::failed;
            }
            if (message->binary) {
                continue;
            }
            if (message->text.find(std::string("\"type\":\"") + type + "\"") != std::string::npos) {
                return Reply::expected;
            }
            if (message->text.find("\"type\":\"error\"") != std::string::npos) {
                report_.fail(index_, message->text);
                return is_rate_limited(message->text) ? Reply::rate_limited : Reply::failed;
            }
        }
    }

    static bool is_rate_limited(const std::string& error_text) {
        return error_text.find(std::string("\"code\":\"") +
                               std::string(base::name_of(base::ErrorCode::rate_limited)) + "\"") !=
               std::string::npos;
    }

    // Moves the camera, asks for frame `id` and waits for it, or for an error naming `id`; false
    // where the connection failed.
    bool request_frame(double azimuth, std::int64_t id) {
        (void)client_->send_text(R"({"v":1,"type":"set","camera":{"orbit":{"azimuth":)" +
                                 std::to_string(azimuth) + R"(,"elevation":10,"distance":2.6}}})");
        const Clock::time_point sent = Clock::now();
        (void)client_->send_text(R"({"v":1,"type":"render","id":)" + std::to_string(id) +
                                 (config_.interactive ? R"(,"interactive":true})" : "}"));
        while (true) {
            auto message = client_->receive(reply_timeout);
            if (!message) {
                report_.fail(index_, message.error().to_string());
                return false;
            }
            if (!message->binary) {
                if (message->text.find("\"type\":\"error\"") != std::string::npos) {
                    report_.fail(index_, message->text);
                    // An error naming this request (rate_limited, too_much_work) is its answer:
                    // no frame follows.
                    if (protocol::request_id_of(message->text) == id) {
                        if (is_rate_limited(message->text)) {
                            back_off();
                        } else {
                            refusals_ = 0;
                        }
                        return true;
                    }
                }
                continue;
            }
            const Clock::time_point received = Clock::now();
            auto frame = protocol::unpack_frame(message->bytes);
            if (!frame) {
                report_.fail(index_, frame.error().to_string());
                return false;
            }
            const protocol::FrameHeader& h = frame->header;
            if (h.refinement > 0) {
                // A refinement step of an earlier still: it answers no request of this loop.
                report_.add_refinement_frame();
            } else if (h.request == id && !h.preview) {  // a preview: the still follows
                report_.add({ms_between(sent, received), h.queued_ms, h.render_ms, h.readback_ms,
                             h.encode_ms, message->bytes.size()});
                refusals_ = 0;
                return true;
            }
            // else an earlier frame; ours is still coming
        }
    }

    // Over the rate limit the client waits before its next request, as a browser's would, longer
    // each time in a row: the server stops answering a client that keeps sending into its limit.
    // The wait ends with the run.
    void back_off() {
        ++refusals_;
        const Clock::time_point resume = Clock::now() + rate_limited_backoff(refusals_);
        std::this_thread::sleep_until(std::min(resume, end_));
    }

    int index_;
    const LoadConfig& config_;
    SharedReport& report_;
    std::unique_ptr<Client> client_;
    Clock::time_point end_;
    int refusals_ = 0;          // rate_limited answers in a row
    std::int64_t last_id_ = 0;  // of the last request sent: settings and renders count alike
};

// Each part of the latency over the samples, in the report's row order.
struct LatencyParts {
    std::vector<double> latency, queued, render, readback, encode, send;
    std::size_t bytes = 0;

    explicit LatencyParts(const std::vector<LoadSample>& samples) {
        for (const LoadSample& s : samples) {
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
    }
};

}  // namespace

std::chrono::milliseconds rate_limited_backoff(int refusals) {
    constexpr std::chrono::milliseconds first{250};
    constexpr std::chrono::milliseconds longest{4000};
    std::chrono::milliseconds wait = first;
    for (int i = 1; i < refusals && wait < longest; ++i) {
        wait *= 2;
    }
    return std::min(wait, longest);
}

std::string load_path(const std::string& volume, const std::string& token) {
    std::string path = "/ws?volume=" + url_encode(volume);
    if (!token.empty()) {
        path += "&token=" + url_encode(token);
    }
    return path;
}

LoadReport run_load(const LoadConfig& config) {
    SharedReport shared;
    const Clock::time_point start = Clock::now();
    const Clock::time_point end = start + std::chrono::duration_cast<Clock::duration>(
                                                  std::chrono::duration<double>(config.seconds));
    std::vector<std::thread> threads;
    threads.reserve(static_cast<std::size_t>(std::max(config.clients, 0)));
    for (int i = 0; i < config.clients; ++i) {
        threads.emplace_back(
                [i, &config, &shared, end] { LoadClient(i, config, shared).run(end); });
    }
    for (auto& t : threads) {
        t.join();
    }
    LoadReport report = shared.take();
    report.elapsed_s = ms_between(start, Clock::now()) / 1000.0;
    return report;
}

void print_load_report(const LoadConfig& config, const LoadReport& report, std::FILE* out) {
    const LatencyParts parts(report.samples);
    const double elapsed = report.elapsed_s;
    const auto frames = static_cast<double>(parts.latency.size());
    const double kib = static_cast<double>(parts.bytes) / 1024.0;
    std::fprintf(out, "load:     %d client(s), %s %dx%d %s, %.1f s against %s:%u\n", config.clients,
                 config.mode.c_str(), config.size, config.size,
                 config.encoding.empty() ? "(the session's encoding)" : config.encoding.c_str(),
                 elapsed, config.host.c_str(), config.port);
    std::fprintf(out, "frames:   %zu (%.2f frames/s), %.1f KiB/frame, %.1f KiB/s, errors %llu\n",
                 parts.latency.size(), frames / elapsed, frames > 0.0 ? kib / frames : 0.0,
                 kib / elapsed, static_cast<unsigned long long>(report.errors));
    if (config.refine > 0) {
        std::fprintf(out, "refined:  %llu refinement frames besides those answering requests\n",
                     static_cast<unsigned long long>(report.refinement_frames));
    }
    std::fprintf(out, "%-22s %10s %10s %10s\n", "ms", "p50", "p95", "p99");
    const auto row = [out](const char* name, const std::vector<double>& v) {
        std::fprintf(out, "%-22s %10.2f %10.2f %10.2f\n", name, percentile(v, 0.50),
                     percentile(v, 0.95), percentile(v, 0.99));
    };
    row("latency (client)", parts.latency);
    row("  queued (server)", parts.queued);
    row("  render (server)", parts.render);
    row("  readback (server)", parts.readback);
    row("  encode (server)", parts.encode);
    row("  send + network", parts.send);
    for (const auto& text : report.error_texts) {
        std::fprintf(out, "error:    %s\n", text.c_str());
    }
}

}  // namespace penumbra::net
