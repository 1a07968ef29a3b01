#include <penumbra/encode/compare.hpp>
#include <penumbra/encode/encode.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <string_view>

namespace penumbra::encode {
namespace {

base::ImageRgba8 gradient_image(int w, int h) {
    base::ImageRgba8 image(w, h);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            std::uint8_t* p = image.pixel(x, y);
            p[0] = static_cast<std::uint8_t>(x * 255 / (w - 1));
            p[1] = static_cast<std::uint8_t>(y * 255 / (h - 1));
            p[2] = 77;
            p[3] = 255;
        }
    }
    return image;
}

TEST(Encode, PngRoundTripIsLossless) {
    const base::ImageRgba8 image = gradient_image(37, 21);
    auto bytes = encode_image(image, ImageFormat::png);
    ASSERT_TRUE(bytes.ok()) << bytes.error().to_string();
    EXPECT_EQ((*bytes)[1], 'P');
    auto decoded = decode_image(*bytes);
    ASSERT_TRUE(decoded.ok()) << decoded.error().to_string();
    EXPECT_EQ(decoded->width, 37);
    EXPECT_EQ(decoded->height, 21);
    EXPECT_EQ(decoded->pixels, image.pixels);
}

TEST(Encode, JpegIsCloseAndQualityChangesSize) {
    const base::ImageRgba8 image = gradient_image(64, 64);
    auto high = encode_image(image, ImageFormat::jpeg, 95);
    auto low = encode_image(image, ImageFormat::jpeg, 10);
    ASSERT_TRUE(high.ok() && low.ok());
    EXPECT_EQ((*high)[0], 0xFF);
    EXPECT_EQ((*high)[1], 0xD8);
    EXPECT_LT(low->size(), high->size());
    auto decoded = decode_image(*high);
    ASSERT_TRUE(decoded.ok());
    auto difference = compare_images(base::to_rgba_f(image), base::to_rgba_f(*decoded));
    ASSERT_TRUE(difference.ok());
    EXPECT_GT(difference->psnr, 35.0);
}

TEST(Encode, RejectsBadQualityEmptyImagesAndGarbage) {
    EXPECT_EQ(encode_image(gradient_image(4, 4), ImageFormat::jpeg, 0).error().code,
              base::ErrorCode::invalid_value);
    EXPECT_EQ(encode_image(base::ImageRgba8(), ImageFormat::png).error().code,
              base::ErrorCode::encode_failed);
    const std::vector<std::uint8_t> garbage(100, 0x42);
    EXPECT_EQ(decode_image(garbage).error().code, base::ErrorCode::decode_failed);
    std::vector<std::uint8_t> truncated =
            encode_image(gradient_image(16, 16), ImageFormat::png).value();
    truncated.resize(40);
    EXPECT_FALSE(decode_image(truncated).ok());
}

TEST(Encode, WritesFilesByExtension) {
    const auto dir = std::filesystem::temp_directory_path() / "penumbra_encode_test";
    std::filesystem::create_directories(dir);
    ASSERT_TRUE(write_image(dir / "a.png", gradient_image(8, 8)).ok());
    ASSERT_TRUE(write_image(dir / "a.JPG", gradient_image(8, 8)).ok());
    EXPECT_EQ(write_image(dir / "a.bmp", gradient_image(8, 8)).error().code,
              base::ErrorCode::unsupported_format);
    auto back = read_image(dir / "a.png");
    ASSERT_TRUE(back.ok());
    EXPECT_EQ(back->pixels, gradient_image(8, 8).pixels);
    std::filesystem::remove_all(dir);
}

TEST(Compare, IdenticalImagesHaveInfinitePsnrAndKnownOffsetHasKnownRmse) {
    base::ImageRgbaF a(4, 4);
    base::ImageRgbaF b(4, 4);
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        a.pixels[i] = 0.5f;
        b.pixels[i] = (i % 4 == 3) ? 0.0f : 0.6f;  // alpha differs, but alpha is ignored
    }
    a.pixels[3] = 1.0f;
    auto same = compare_images(a, a);
    ASSERT_TRUE(same.ok());
    EXPECT_TRUE(std::isinf(same->psnr));
    auto diff = compare_images(a, b);
    ASSERT_TRUE(diff.ok());
    EXPECT_NEAR(diff->rms_error, 0.1, 1e-6);
    EXPECT_NEAR(diff->psnr, 20.0, 1e-4);
    EXPECT_EQ(compare_images(a, base::ImageRgbaF(2, 2)).error().code,
              base::ErrorCode::size_mismatch);
}

}  // namespace
}  // namespace penumbra::encode
