#pragma once

// The load generator of `penumbra load`: simulated users on one server, each orbiting the camera
// and waiting for each frame before asking for the next (closed loop, like a client pacing one
// request in flight); the latency from request sent to frame received, with the server's split
// from each frame's header.

#include <penumbra/scene/frame_request.hpp>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace penumbra::net {

struct LoadConfig {
    std::string host = "127.0.0.1";
    unsigned short port = 0;
    int clients = 4;
    double seconds = 10.0;
    std::string volume = "ch2.nii.gz";  // an id from list_volumes
    std::string mode = "sbrc";
    int size = 512;  // frames of size x size pixels
    // One of scene::kFrameFormatNames; the first, as a new session's.
    std::string encoding{scene::name_of(scene::FrameFormat{})};
    bool interactive = false;
    // > 0: jittered frames, each still refined this many times (progressive stills); 0: stills
    // not refined.
    int refine = 0;
    std::string token;  // the access token a server or proxy asks for; empty: none
};

// One frame that answered a request.
struct LoadSample {
    double latency_ms = 0.0;  // request sent -> frame received, measured by the client
    double queued_ms = 0.0;
    double render_ms = 0.0;
    double readback_ms = 0.0;
    double encode_ms = 0.0;
    std::size_t bytes = 0;
};

struct LoadReport {
    double elapsed_s = 0.0;
    std::vector<LoadSample> samples;
    std::uint64_t errors = 0;
    std::vector<std::string> error_texts;  // the first few, each naming its client
    std::uint64_t refinement_frames = 0;   // progressive refinement steps received

    // Every client ran without an error and at least one frame came back.
    [[nodiscard]] bool ok() const { return errors == 0 && !samples.empty(); }
};

// "/ws?volume=ID[&token=T]": the WebSocket URL names the volume, as a cluster's proxy routes by
// it (proto/README.md §1); both values encoded as browsers encode a query, so that every client
// writes a volume alike and a proxy hashes it alike.
std::string load_path(const std::string& volume, const std::string& token);

// Runs `config.clients` simulated users for `config.seconds`, each on a thread of its own and
// each asking at least one frame once its session is open, however long the open took. An
// error naming a request answers it; a client refused with rate_limited waits
// rate_limited_backoff before its next request, and asks again for its session (the open and
// the first `set`, the frame's settings) where those were refused.
LoadReport run_load(const LoadConfig& config);

// How long a load client waits after the `refusals`-th rate_limited answer in a row (from 1):
// 250 ms, doubling up to 4 s.
std::chrono::milliseconds rate_limited_backoff(int refusals);

// The report as `penumbra load` prints it: the run, frames/s and bytes/s, and p50/p95/p99 of
// the latency and of its parts.
void print_load_report(const LoadConfig& config, const LoadReport& report, std::FILE* out);

}  // namespace penumbra::net
