#pragma once

#include <penumbra/scene/frame_request.hpp>

#include <cstddef>
#include <string_view>

namespace penumbra::protocol {

// What the server accepts, announced in `hello` so clients can stay inside it. Configurable per
// server (penumbra serve options).
struct Limits {
    std::size_t max_message_bytes = 64 * 1024;
    int max_image_side = 2048;
    int max_slices = 1024;
    int max_light_resolution = 1024;
    int max_sessions = 64;
    // Sessions one client may hold: opened by one remote address (behind a proxy, the address
    // its header names), and opened by one connection and still running.
    int max_sessions_per_client = 16;
    int max_sessions_per_connection = 4;
    double max_requests_per_second = 120.0;  // per connection, averaged over one second
    int max_send_queue = 4;                  // frames waiting per connection before dropping
    // Shader iterations one frame may ask for (scene::estimate_work, an upper bound for any
    // camera: with empty-space skipping, per ray the samples that fit along the longest line
    // through the bricks the frame's TF leaves visible, plus one per brick leapt, never more
    // than without skipping): a 512^2 reference frame at sample distance 1/256 of a fully
    // visible volume asks for 5e10, a 2048^2 sbrc_shell frame at the default settings 2e10.
    double max_frame_work = 1e11;
    // The largest side of an exported still (rendered in tiles of at most max_image_side and
    // session::ExportLimits::tile_side).
    int max_export_side = 4096;
    // A movie's largest side and most frames (export_movie); no frames where the server writes
    // no movies (a build without FFmpeg's libraries).
    int max_movie_side = 1920;
    int max_movie_frames = 720;
    // Containers nested in one JSON text (the message object is 1; the deepest valid message
    // has 5). Checked while parsing, so no deeper document is ever built or walked.
    int max_json_depth = 16;
};

// The part of `limits` that scene::validate and scene::starting_frame hold a frame to.
inline scene::Limits scene_limits(const Limits& limits) {
    return {limits.max_image_side, limits.max_slices, limits.max_light_resolution};
}

// Fixed by the protocol rather than configured, announced in `hello.limits` with the rest: the
// points a transfer function's colour or opacity list may hold, and the bytes of its name.
inline constexpr std::size_t max_transfer_function_points = 256;
inline constexpr std::size_t max_transfer_function_name_bytes = 64;
// The name a transfer function given by its points takes when the patch names none.
inline constexpr std::string_view unnamed_transfer_function = "custom";

inline constexpr int protocol_version = 1;

}  // namespace penumbra::protocol
