#include <penumbra/encode/encode.hpp>
#include <penumbra/session/session_stream.hpp>

namespace penumbra::session {

static_assert(scene::setting::h264_quality.min == encode::kMinStreamQuality &&
              scene::setting::h264_quality.max == encode::kMaxStreamQuality);

encode::StreamOptions stream_options(const scene::Output& output) {
    encode::StreamOptions options;
    switch (output.format) {
        case scene::FrameFormat::jpeg:
            options.codec = encode::StreamCodec::jpeg;
            break;
        case scene::FrameFormat::png:
            options.codec = encode::StreamCodec::png;
            break;
        case scene::FrameFormat::h264:
            options.codec = encode::StreamCodec::h264;
            break;
    }
    options.jpeg_quality = output.jpeg_quality;
    options.h264_quality = output.h264_quality;
    return options;
}

scene::FrameFormat frame_format(const scene::Output& output, bool final_still) {
    return final_still && output.format == scene::FrameFormat::h264 ? scene::FrameFormat::jpeg
                                                                    : output.format;
}

base::Result<encode::StreamFrame> SessionStream::encode(const base::ImageRgba8& image,
                                                        const scene::Output& output,
                                                        bool final_still) {
    const std::lock_guard lock(mutex_);
    if (frame_format(output, final_still) != output.format) {
        auto bytes = encode::encode_image(image, encode::ImageFormat::jpeg, output.jpeg_quality);
        if (!bytes) {
            return bytes.error();
        }
        keyframe_wanted_.store(true);
        return encode::StreamFrame{std::move(bytes.value()), true};
    }
    if (!stream_ || made_for_ != output) {
        auto made = encode::make_stream(stream_options(output));
        if (!made) {
            return made.error();
        }
        stream_ = std::move(made.value());
        made_for_ = output;
    }
    auto frame = stream_->encode(image, keyframe_wanted_.exchange(false));
    if (!frame) {
        // What the encoder holds is unknown now: the next frame starts a new stream, a keyframe.
        stream_.reset();
    }
    return frame;
}

}  // namespace penumbra::session
