#include <penumbra/encode/stream.hpp>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libswscale/swscale.h>
}

#include <cstring>

namespace penumbra::encode {
namespace {

base::Error decode_error(const std::string& what) {
    return base::make_error(base::ErrorCode::decode_failed, what, "h264");
}

}  // namespace

struct StreamDecoder::Impl {
    AVCodecContext* codec = nullptr;
    AVPacket* packet = nullptr;
    AVFrame* frame = nullptr;
    SwsContext* convert = nullptr;

    ~Impl() {
        sws_freeContext(convert);
        av_frame_free(&frame);
        av_packet_free(&packet);
        avcodec_free_context(&codec);
    }
};

StreamDecoder::StreamDecoder(std::unique_ptr<Impl> impl)
    : impl_(std::move(impl)) {}

StreamDecoder::StreamDecoder(StreamDecoder&&) noexcept = default;
StreamDecoder& StreamDecoder::operator=(StreamDecoder&&) noexcept = default;
StreamDecoder::~StreamDecoder() = default;

base::Result<StreamDecoder> StreamDecoder::create() {
    const AVCodec* h264 = avcodec_find_decoder(AV_CODEC_ID_H264);
    if (h264 == nullptr) {
        return decode_error("this libavcodec has no H.264 decoder");
    }
    auto impl = std::make_unique<Impl>();
    impl->codec = avcodec_alloc_context3(h264);
    impl->packet = av_packet_alloc();
    impl->frame = av_frame_alloc();
    if (impl->codec == nullptr || impl->packet == nullptr || impl->frame == nullptr) {
        return decode_error("out of memory");
    }
    impl->codec->flags |= AV_CODEC_FLAG_LOW_DELAY;
    impl->codec->thread_count = 1;
    if (avcodec_open2(impl->codec, h264, nullptr) < 0) {
        return decode_error("opening the H.264 decoder failed");
    }
    return StreamDecoder(std::move(impl));
}

base::Result<base::ImageRgba8> StreamDecoder::decode(std::span<const std::uint8_t> unit) {
    Impl& impl = *impl_;
    if (av_new_packet(impl.packet, static_cast<int>(unit.size())) < 0) {
        return decode_error("out of memory for a packet");
    }
    std::memcpy(impl.packet->data, unit.data(), unit.size());
    const int sent = avcodec_send_packet(impl.codec, impl.packet);
    av_packet_unref(impl.packet);
    if (sent < 0 || avcodec_receive_frame(impl.codec, impl.frame) != 0) {
        return decode_error("the access unit gave no picture");
    }
    const AVFrame& frame = *impl.frame;
    impl.convert = sws_getCachedContext(
            impl.convert, frame.width, frame.height, static_cast<AVPixelFormat>(frame.format),
            frame.width, frame.height, AV_PIX_FMT_RGBA, SWS_BICUBIC, nullptr, nullptr, nullptr);
    if (impl.convert == nullptr) {
        return decode_error("no conversion of the picture to RGBA");
    }
    base::ImageRgba8 image(frame.width, frame.height);
    std::uint8_t* target[1] = {image.pixels.data()};
    const int stride[1] = {4 * image.width};
    sws_scale(impl.convert, frame.data, frame.linesize, 0, frame.height, target, stride);
    return image;
}

}  // namespace penumbra::encode
