// A session's frame stream as a client decodes it: H.264 access units fed one by one to
// libavcodec's decoder (encode::StreamDecoder; what Chromium's WebCodecs runs in software), from
// the first frame or from a keyframe a joining viewer starts at; JPEG and PNG frames each alone.

#include "moving_square.hpp"

#include <penumbra/encode/stream.hpp>
#include <penumbra/imageio/imageio.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace penumbra::encode {
namespace {

// A client's decoder: each access unit fed gives its picture at once, or nothing.
class Decoder {
public:
    Decoder()
        : decoder_(StreamDecoder::create()) {
        EXPECT_TRUE(decoder_.ok()) << (decoder_.ok() ? "" : decoder_.error().to_string());
    }

    std::optional<base::ImageRgba8> decode(const std::vector<std::uint8_t>& unit) {
        auto image = decoder_->decode(unit);
        return image.ok() ? std::optional(std::move(image.value())) : std::nullopt;
    }

private:
    base::Result<StreamDecoder> decoder_;
};

std::unique_ptr<FrameStream> h264_stream(int quality = 20) {
    auto stream = make_stream({.codec = StreamCodec::h264, .h264_quality = quality});
    EXPECT_TRUE(stream.ok()) << (stream.ok() ? "" : stream.error().to_string());
    return stream.ok() ? std::move(stream.value()) : nullptr;
}

// The first frame is a keyframe and the rest are not; each access unit decodes at once into its
// own frame, in order.
TEST(FrameStream, H264FramesDecodeOneByOneInOrderAfterTheFirstKeyframe) {
    auto stream = h264_stream();
    ASSERT_NE(stream, nullptr);
    EXPECT_EQ(stream->codec(), StreamCodec::h264);
    Decoder decoder;
    for (int k = 0; k < 10; ++k) {
        const base::ImageRgba8 image = moving_square(64, 48, k);
        auto frame = stream->encode(image, false);
        ASSERT_TRUE(frame.ok()) << frame.error().to_string();
        EXPECT_EQ(frame->independent, k == 0) << "frame " << k;
        auto decoded = decoder.decode(frame->bytes);
        ASSERT_TRUE(decoded) << "frame " << k << " gave no picture at once";
        ASSERT_EQ(decoded->width, 64);
        ASSERT_EQ(decoded->height, 48);
        EXPECT_GT(psnr(*decoded, image), 26.0) << "frame " << k;
        if (k > 0) {
            EXPECT_GT(psnr(*decoded, image), psnr(*decoded, moving_square(64, 48, k - 1)) + 3.0);
        }
    }
}

// A viewer who joins, or one whose frame was dropped, starts from a frame asked to be
// independent: a decoder that saw nothing before it decodes it and every frame after. A frame of
// a new size (the view resized) is independent without being asked; an odd size decodes one
// column and row larger, the image at its top left.
TEST(FrameStream, AKeyframeWhenAskedOrResizedStartsANewDecoderAndOddSizesKeepTheirSize) {
    auto stream = h264_stream();
    ASSERT_NE(stream, nullptr);
    for (int k = 0; k < 4; ++k) {
        ASSERT_TRUE(stream->encode(moving_square(64, 48, k), false).ok());
    }
    auto joined = stream->encode(moving_square(64, 48, 4), true);
    ASSERT_TRUE(joined.ok());
    EXPECT_TRUE(joined->independent);
    Decoder joiner;
    ASSERT_TRUE(joiner.decode(joined->bytes));
    for (int k = 5; k < 8; ++k) {
        auto frame = stream->encode(moving_square(64, 48, k), false);
        ASSERT_TRUE(frame.ok());
        EXPECT_FALSE(frame->independent);
        auto decoded = joiner.decode(frame->bytes);
        ASSERT_TRUE(decoded) << "frame " << k;
        EXPECT_GT(psnr(*decoded, moving_square(64, 48, k)), 26.0);
    }

    auto resized = stream->encode(moving_square(81, 61, 8), false);
    ASSERT_TRUE(resized.ok()) << resized.error().to_string();
    EXPECT_TRUE(resized->independent) << "a new size starts afresh";
    Decoder fresh;
    auto decoded = fresh.decode(resized->bytes);
    ASSERT_TRUE(decoded);
    ASSERT_EQ(decoded->width, 82);
    ASSERT_EQ(decoded->height, 62);
    base::ImageRgba8 cropped(81, 61);
    for (int y = 0; y < 61; ++y) {
        std::copy_n(decoded->pixel(0, y), 4 * 81, cropped.pixel(0, y));
    }
    EXPECT_GT(psnr(cropped, moving_square(81, 61, 8)), 26.0);
}

// An unchanged frame (a still whose view did not move) costs a few bytes.
TEST(FrameStream, AnUnchangedFrameCostsAFewBytes) {
    auto stream = h264_stream();
    ASSERT_NE(stream, nullptr);
    const base::ImageRgba8 image = moving_square(512, 512, 3);
    auto first = stream->encode(image, false);
    ASSERT_TRUE(first.ok());
    for (int k = 0; k < 3; ++k) {
        auto again = stream->encode(image, false);
        ASSERT_TRUE(again.ok());
        EXPECT_LE(again->bytes.size(), 200u) << "repeat " << k;
    }
}

// JPEG and PNG frames stand alone whatever is asked, and decode as images.
TEST(FrameStream, JpegAndPngFramesAreEachIndependentImages) {
    for (const StreamCodec codec : {StreamCodec::jpeg, StreamCodec::png}) {
        auto stream = make_stream({.codec = codec, .jpeg_quality = 90});
        ASSERT_TRUE(stream.ok());
        EXPECT_EQ((*stream)->codec(), codec);
        for (int k = 0; k < 3; ++k) {
            auto frame = (*stream)->encode(moving_square(64, 48, k), false);
            ASSERT_TRUE(frame.ok());
            EXPECT_TRUE(frame->independent);
            auto decoded = imageio::decode_image(frame->bytes);
            ASSERT_TRUE(decoded.ok());
            EXPECT_EQ(decoded->width, 64);
        }
    }
}

TEST(FrameStream, QualitiesAndRatesOutOfRangeAreRefused) {
    EXPECT_FALSE(make_stream({.codec = StreamCodec::h264, .h264_quality = 52}).ok());
    EXPECT_FALSE(make_stream({.codec = StreamCodec::h264, .h264_quality = 0}).ok());
    // The finest rate factor allowed encodes (the high profile has no lossless).
    auto finest = make_stream({.codec = StreamCodec::h264, .h264_quality = kMinStreamQuality});
    ASSERT_TRUE(finest.ok());
    EXPECT_TRUE((*finest)->encode(moving_square(32, 32, 0), false).ok());
    EXPECT_FALSE(make_stream({.codec = StreamCodec::jpeg, .jpeg_quality = 0}).ok());
    EXPECT_FALSE(make_stream({.codec = StreamCodec::h264, .frames_per_second = 0}).ok());
    auto stream = make_stream({.codec = StreamCodec::h264});
    ASSERT_TRUE(stream.ok());
    EXPECT_FALSE((*stream)->encode(base::ImageRgba8(), false).ok());
}

}  // namespace
}  // namespace penumbra::encode
