#pragma once

#include <cstddef>

namespace penumbra::protocol {

// What the server accepts, announced in `hello` so clients can stay inside it. Configurable per
// server (penumbra serve options).
struct Limits {
    std::size_t max_message_bytes = 64 * 1024;
    int max_image_side = 2048;
    int max_slices = 1024;
    int max_light_resolution = 1024;
    int max_sessions = 64;
    double max_requests_per_second = 120.0;  // per connection, averaged over one second
    int max_send_queue = 4;                  // frames waiting per connection before dropping
    // Containers nested in one JSON text (the message object is 1; the deepest valid message
    // has 5). Checked while parsing, so no deeper document is ever built or walked.
    int max_json_depth = 16;
};

inline constexpr int protocol_version = 1;

}  // namespace penumbra::protocol
