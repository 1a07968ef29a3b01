#pragma once

// A session's frames as a stream: each session owns one (DESIGN.md §4), so that a codec may send
// what changed since the frame before. JPEG and PNG are intra-only: every frame stands alone. H.264
// (libx264: no B-frames, no look-ahead, one access unit per frame, Annex B with its parameter sets
// before every keyframe, the form WebCodecs' VideoDecoder takes) sends most frames as the change
// from the one before; a frame asked to be independent (a viewer joined, a frame was dropped, a
// resume) or of another size than the last is a keyframe. H.264 pictures have even sides: an odd
// side is padded by one column or row, which a client crops by the frame's own size.

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/encode/encode.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace penumbra::encode {

enum class StreamCodec { jpeg, png, h264 };

// x264's constant rate factors a stream may take, 1 .. 51 (fewer bytes): 0 would be lossless,
// which the high profile (what browsers decode) does not allow.
inline constexpr int kMinStreamQuality = 1;
inline constexpr int kMaxStreamQuality = 51;

struct StreamOptions {
    StreamCodec codec = StreamCodec::jpeg;
    int jpeg_quality = 85;  // kMinJpegQuality..kMaxJpegQuality
    int h264_quality = 23;  // x264's constant rate factor, kMinStreamQuality..kMaxStreamQuality
    int frames_per_second = 30;  // what the rate control assumes of a stream's pace
};

struct StreamFrame {
    std::vector<std::uint8_t> bytes;
    // Decodable without any frame before it. A frame that is not may be dropped only with every
    // frame after it up to the next independent one.
    bool independent = true;
};

class FrameStream {
public:
    virtual ~FrameStream() = default;

    // Encodes the next frame of the stream; `independent` asks for one that decodes alone. A
    // frame of another size than the one before is independent whatever is asked.
    virtual base::Result<StreamFrame> encode(const base::ImageRgba8& image, bool independent) = 0;

    [[nodiscard]] virtual StreamCodec codec() const = 0;
};

// A stream of `options.codec`. Errors: invalid_value for a quality or rate out of range,
// encode_failed where the encoder cannot start.
base::Result<std::unique_ptr<FrameStream>> make_stream(const StreamOptions& options);

// An H.264 stream's access units decoded one by one as a client's decoder does (libavcodec, low
// delay: each unit's picture at once), for the tests and the stream benchmark. A build without
// FFmpeg (PENUMBRA_WITH_FFMPEG off) has none: create() says so.
class StreamDecoder {
public:
    static base::Result<StreamDecoder> create();

    StreamDecoder(StreamDecoder&&) noexcept;
    StreamDecoder& operator=(StreamDecoder&&) noexcept;
    ~StreamDecoder();

    // The picture `unit` decodes to, RGBA at the stream's (even) size; an error where it gives
    // none (it needs a keyframe this decoder has not seen, or is no H.264).
    base::Result<base::ImageRgba8> decode(std::span<const std::uint8_t> unit);

private:
    struct Impl;
    explicit StreamDecoder(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra::encode
