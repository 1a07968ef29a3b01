#include "movie_reader.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
}

#include <gtest/gtest.h>

#include <cstdint>

namespace penumbra::test {

ReadMovie read_movie(const std::filesystem::path& path) {
    ReadMovie out;
    AVFormatContext* format = nullptr;
    EXPECT_EQ(avformat_open_input(&format, path.c_str(), nullptr, nullptr), 0);
    if (format == nullptr) {
        return out;
    }
    EXPECT_GE(avformat_find_stream_info(format, nullptr), 0);
    EXPECT_EQ(format->nb_streams, 1u);
    const AVStream* stream = format->streams[0];
    const AVCodec* decoder = avcodec_find_decoder(stream->codecpar->codec_id);
    out.codec = avcodec_get_name(stream->codecpar->codec_id);
    out.width = stream->codecpar->width;
    out.height = stream->codecpar->height;
    out.frames_per_second = av_q2d(stream->avg_frame_rate);
    AVCodecContext* codec = avcodec_alloc_context3(decoder);
    avcodec_parameters_to_context(codec, stream->codecpar);
    EXPECT_EQ(avcodec_open2(codec, decoder, nullptr), 0);
    AVPacket* packet = av_packet_alloc();
    AVFrame* frame = av_frame_alloc();
    SwsContext* convert = nullptr;
    const auto receive = [&] {
        while (avcodec_receive_frame(codec, frame) == 0) {
            convert = sws_getCachedContext(convert, frame->width, frame->height,
                                           static_cast<AVPixelFormat>(frame->format), frame->width,
                                           frame->height, AV_PIX_FMT_RGBA, SWS_BICUBIC, nullptr,
                                           nullptr, nullptr);
            base::ImageRgba8 image(frame->width, frame->height);
            std::uint8_t* target[1] = {image.pixels.data()};
            const int stride[1] = {4 * image.width};
            sws_scale(convert, frame->data, frame->linesize, 0, frame->height, target, stride);
            out.frames.push_back(std::move(image));
        }
    };
    while (av_read_frame(format, packet) == 0) {
        avcodec_send_packet(codec, packet);
        av_packet_unref(packet);
        receive();
    }
    avcodec_send_packet(codec, nullptr);
    receive();
    sws_freeContext(convert);
    av_frame_free(&frame);
    av_packet_free(&packet);
    avcodec_free_context(&codec);
    avformat_close_input(&format);
    return out;
}

}  // namespace penumbra::test
