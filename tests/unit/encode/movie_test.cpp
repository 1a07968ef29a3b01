// Movies as a player reads them: the MP4 that MovieWriter writes is opened with libavformat and
// decoded with libavcodec here, frame by frame, against the frames given.

#include <penumbra/encode/movie.hpp>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
}

#include "moving_square.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace penumbra::encode {
namespace {

namespace fs = std::filesystem;

struct ReadMovie {
    std::string codec;
    int width = 0;
    int height = 0;
    double frames_per_second = 0.0;
    std::vector<base::ImageRgba8> frames;
};

// Every frame of the movie in `path`, decoded and turned back into RGBA.
ReadMovie read_movie(const fs::path& path) {
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

class MovieTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("penumbra_movie_" +
                std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
    }

    void TearDown() override { fs::remove_all(dir_); }

    fs::path dir_;
};

TEST_F(MovieTest, AnMp4HoldsEveryFrameAtItsSizeAndRateAsGiven) {
    const fs::path path = dir_ / "square.mp4";
    auto writer = MovieWriter::create(path, 64, 48, {.frames_per_second = 24, .quality = 18});
    ASSERT_TRUE(writer.ok()) << writer.error().to_string();
    constexpr int frames = 12;
    for (int k = 0; k < frames; ++k) {
        ASSERT_TRUE(writer->add(moving_square(64, 48, k)).ok());
    }
    ASSERT_TRUE(writer->finish().ok());
    EXPECT_EQ(writer->frames(), frames);
    EXPECT_FALSE(writer->add(moving_square(64, 48, 0)).ok()) << "nothing after finish";

    const ReadMovie movie = read_movie(path);
    EXPECT_EQ(movie.codec, "h264");
    EXPECT_EQ(movie.width, 64);
    EXPECT_EQ(movie.height, 48);
    EXPECT_NEAR(movie.frames_per_second, 24.0, 1e-6);
    ASSERT_EQ(movie.frames.size(), std::size_t(frames));
    for (int k = 0; k < frames; ++k) {
        // In their order: each frame is nearest the frame given at its place.
        const double own = psnr(movie.frames[k], moving_square(64, 48, k));
        EXPECT_GT(own, 26.0) << "frame " << k;  // 4:2:0 blurs the square's coloured edges
        if (k > 0) {
            EXPECT_GT(own, psnr(movie.frames[k], moving_square(64, 48, k - 1)) + 3.0)
                    << "frame " << k;
        }
    }
}

TEST_F(MovieTest, AMovieMadeInMemoryIsTheSameMp4AndKeepsToItsLimit) {
    constexpr int frames = 8;
    auto in_memory = MovieWriter::create_in_memory(64, 48, {.frames_per_second = 24, .quality = 18},
                                                   std::size_t{1} << 20);
    ASSERT_TRUE(in_memory.ok()) << in_memory.error().to_string();
    auto in_file = MovieWriter::create(dir_ / "file.mp4", 64, 48,
                                       {.frames_per_second = 24, .quality = 18});
    ASSERT_TRUE(in_file.ok());
    EXPECT_TRUE(in_memory->take_bytes().empty()) << "nothing before finish";
    for (int k = 0; k < frames; ++k) {
        ASSERT_TRUE(in_memory->add(moving_square(64, 48, k)).ok());
        ASSERT_TRUE(in_file->add(moving_square(64, 48, k)).ok());
    }
    ASSERT_TRUE(in_memory->finish().ok());
    ASSERT_TRUE(in_file->finish().ok());
    const std::vector<std::uint8_t> bytes = in_memory->take_bytes();
    ASSERT_FALSE(bytes.empty());
    EXPECT_EQ(bytes.size(), fs::file_size(dir_ / "file.mp4")) << "the index points back alike";
    {
        std::ofstream(dir_ / "memory.mp4", std::ios::binary)
                .write(reinterpret_cast<const char*>(bytes.data()),
                       static_cast<std::streamsize>(bytes.size()));
    }
    const ReadMovie movie = read_movie(dir_ / "memory.mp4");
    EXPECT_EQ(movie.width, 64);
    EXPECT_EQ(movie.height, 48);
    ASSERT_EQ(movie.frames.size(), std::size_t(frames));
    for (int k = 0; k < frames; ++k) {
        EXPECT_GT(psnr(movie.frames[k], moving_square(64, 48, k)), 26.0) << "frame " << k;
    }

    // A movie larger than its limit fails as too large, however far it got.
    auto small = MovieWriter::create_in_memory(64, 48, {.quality = 0}, 2048);
    ASSERT_TRUE(small.ok());
    base::Status status = base::Ok{};
    for (int k = 0; k < frames && status.ok(); ++k) {
        status = small->add(moving_square(64, 48, k));
    }
    if (status.ok()) {
        status = small->finish();
    }
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.error().code, base::ErrorCode::too_large) << status.error().to_string();
    EXPECT_TRUE(small->take_bytes().empty());
}

TEST_F(MovieTest, BadSizesRatesQualitiesAndFramesAreRefused) {
    const auto refused = [&](const fs::path& path, int width, int height, MovieOptions options) {
        auto writer = MovieWriter::create(path, width, height, options);
        return !writer.ok() && writer.error().code == base::ErrorCode::invalid_argument;
    };
    EXPECT_TRUE(refused(dir_ / "odd.mp4", 63, 48, {}));
    EXPECT_TRUE(refused(dir_ / "huge.mp4", 16384, 48, {}));
    EXPECT_TRUE(refused(dir_ / "movie.avi", 64, 48, {}));
    EXPECT_TRUE(refused(dir_ / "rate.mp4", 64, 48, {.frames_per_second = 0}));
    EXPECT_TRUE(refused(dir_ / "quality.mp4", 64, 48, {.quality = 52}));
    auto unwritable = MovieWriter::create(dir_ / "no" / "such" / "dir.mp4", 64, 48);
    ASSERT_FALSE(unwritable.ok());
    EXPECT_EQ(unwritable.error().code, base::ErrorCode::encode_failed);
    auto writer = MovieWriter::create(dir_ / "sizes.mp4", 64, 48);
    ASSERT_TRUE(writer.ok());
    auto wrong = writer->add(moving_square(48, 64, 0));
    ASSERT_FALSE(wrong.ok());
    EXPECT_NE(wrong.error().message.find("48x64"), std::string::npos) << wrong.error().message;
}

}  // namespace
}  // namespace penumbra::encode
