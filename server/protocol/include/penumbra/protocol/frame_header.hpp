#pragma once

#include <penumbra/base/result.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace penumbra::protocol {

// A frame travels as one binary WebSocket message:
//   bytes 0-3   magic "PNBF"
//   bytes 4-5   protocol version, little endian (1)
//   bytes 6-9   header length H, little endian
//   bytes 10..  H bytes of UTF-8 JSON (FrameHeader, proto/v1/frame_header.schema.json)
//   then        the encoded image (JPEG or PNG)
struct PassTime {
    std::string name;
    double gpu_ms = 0.0;  // -1 where the GL implementation has no usable timer queries
    double wall_ms = 0.0;
};

struct FrameHeader {
    std::uint64_t frame = 0;    // per-session frame counter
    std::int64_t request = -1;  // the id of the render request it answers (-1: none)
    std::string session;
    int width = 0;
    int height = 0;
    std::string encoding;  // "jpeg" | "png" | "h264"
    // Decodable without the frames before it: every JPEG or PNG frame, an H.264 keyframe. An
    // H.264 frame that is not needs every frame since the last keyframe.
    bool independent = true;
    std::string mode;
    bool interactive = false;
    std::string light_buffer;  // "none" | "built" | "reused"
    std::vector<PassTime> passes;
    // Server-side time split, milliseconds.
    double queued_ms = 0.0;
    double render_ms = 0.0;
    double readback_ms = 0.0;
    double encode_ms = 0.0;
    std::string quality;  // a description of the settings actually used
    // Progressive stills: 0 for a frame on its own; k > 0: the still frame refined k times (the
    // mean of k jittered frames of the same view at half its sample distance).
    int refinement = 0;
    // Progressive stills: another refinement step of this still follows; false on the last one
    // (the image stopped changing, or the step limit), and on every frame that is not refined.
    bool refining = false;
    // A still's smaller first frame, sent when the still at full size would take longer than the
    // frame budget; the still follows (refining).
    bool preview = false;
};

std::vector<std::uint8_t> pack_frame(const FrameHeader& header,
                                     std::span<const std::uint8_t> image);

struct UnpackedFrame {
    FrameHeader header;
    std::string header_json;
    std::vector<std::uint8_t> image;
};

base::Result<UnpackedFrame> unpack_frame(std::span<const std::uint8_t> bytes);

}  // namespace penumbra::protocol
