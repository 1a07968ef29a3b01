#include <penumbra/encode/encode.hpp>
#include <penumbra/imageio/compare.hpp>
#include <penumbra/imageio/imageio.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include <png.h>

namespace penumbra::encode {
namespace {

// Decoding and comparing are OpenImageIO's (imageio), which judges what the encoders wrote.
using imageio::compare_images;
using imageio::decode_image;
using imageio::encode_image_openimageio;
using imageio::read_image;

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

// The text chunks of a PNG, read with libpng as any viewer's would.
std::vector<std::pair<std::string, std::string>> png_text_of(const std::vector<std::uint8_t>& png) {
    struct Reader {
        const std::vector<std::uint8_t>* bytes;
        std::size_t at = 0;
    } reader{&png};

    png_structp read = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(read);
    std::vector<std::pair<std::string, std::string>> out;
    if (setjmp(png_jmpbuf(read)) == 0) {
        png_set_read_fn(read, &reader, [](png_structp p, png_bytep data, png_size_t length) {
            auto* r = static_cast<Reader*>(png_get_io_ptr(p));
            std::copy_n(r->bytes->data() + r->at, length, data);
            r->at += length;
        });
        png_read_info(read, info);
        png_textp text = nullptr;
        int count = 0;
        png_get_text(read, info, &text, &count);
        for (int i = 0; i < count; ++i) {
            out.emplace_back(text[i].key, std::string(text[i].text, text[i].text_length));
        }
    }
    png_destroy_read_struct(&read, &info, nullptr);
    return out;
}

// What drew a picture stays with it: a PNG keeps each text given (long text compressed, as a
// frame's settings are), readable by libpng; a keyword PNG cannot hold is refused.
TEST(Encode, APngKeepsItsTextAndABadKeywordIsRefused) {
    base::ImageRgba8 image(8, 4);
    std::fill(image.pixels.begin(), image.pixels.end(), std::uint8_t{90});
    const std::string settings(2000, 'x');
    const std::vector<ImageText> text = {{"Software", "Penumbra"}, {"Penumbra state", settings}};
    auto png = encode_image(image, ImageFormat::png, 90, text);
    ASSERT_TRUE(png.ok()) << png.error().to_string();
    EXPECT_LT(png->size(), settings.size()) << "the long text is compressed";
    const auto read = png_text_of(*png);
    ASSERT_EQ(read.size(), 2u);
    EXPECT_EQ(read[0], std::make_pair(std::string("Software"), std::string("Penumbra")));
    EXPECT_EQ(read[1], std::make_pair(std::string("Penumbra state"), settings));
    for (const std::string& keyword : {std::string(), std::string(80, 'k'), std::string("tab\t")}) {
        const std::vector<ImageText> bad = {{keyword, "x"}};
        auto refused = encode_image(image, ImageFormat::png, 90, bad);
        ASSERT_FALSE(refused.ok()) << "keyword '" << keyword << "'";
        EXPECT_EQ(refused.error().code, base::ErrorCode::invalid_value);
    }
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

// A frame-like image: smooth shading with fine detail and an alpha byte that must be ignored.
base::ImageRgba8 shaded_image(int w, int h) {
    base::ImageRgba8 image(w, h);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            std::uint8_t* p = image.pixel(x, y);
            const double shade = 0.5 + 0.5 * std::sin(x * 0.05) * std::cos(y * 0.07);
            const int detail = ((x * 7 + y * 13) % 17) - 8;
            p[0] = static_cast<std::uint8_t>(std::clamp(shade * 220.0 + detail, 0.0, 255.0));
            p[1] = static_cast<std::uint8_t>(std::clamp(shade * 160.0 + detail, 0.0, 255.0));
            p[2] = static_cast<std::uint8_t>(std::clamp(shade * 120.0, 0.0, 255.0));
            p[3] = static_cast<std::uint8_t>(x * 31 + y);
        }
    }
    return image;
}

// Frames are encoded by TurboJPEG and libpng straight from the RGBA pixels; what they write is
// what OpenImageIO's writers wrote from an RGB copy: JPEG of the same size within 5 % and nearly
// the same pixels, PNG the same pixels exactly (the alpha byte skipped, not written).
TEST(Encode, TheCodecLibrariesWriteWhatOpenImageIoWrote) {
    const base::ImageRgba8 image = shaded_image(160, 96);
    base::ImageRgba8 opaque = image;
    for (std::size_t i = 3; i < opaque.pixels.size(); i += 4) {
        opaque.pixels[i] = 255;
    }
    for (const int quality : {50, 85, 95}) {
        SCOPED_TRACE("JPEG quality " + std::to_string(quality));
        auto codec = encode_image(image, ImageFormat::jpeg, quality);
        auto oiio = encode_image_openimageio(image, ImageFormat::jpeg, quality);
        ASSERT_TRUE(codec.ok() && oiio.ok());
        EXPECT_NEAR(static_cast<double>(codec->size()), static_cast<double>(oiio->size()),
                    0.05 * static_cast<double>(oiio->size()));
        auto from_codec = decode_image(*codec);
        auto from_oiio = decode_image(*oiio);
        ASSERT_TRUE(from_codec.ok() && from_oiio.ok());
        auto difference = compare_images(base::to_rgba_f(*from_codec), base::to_rgba_f(*from_oiio));
        ASSERT_TRUE(difference.ok());
        EXPECT_GT(difference->psnr, 45.0);
    }
    auto png = encode_image(image, ImageFormat::png);
    ASSERT_TRUE(png.ok()) << png.error().to_string();
    auto decoded = decode_image(*png);
    ASSERT_TRUE(decoded.ok()) << decoded.error().to_string();
    EXPECT_EQ(decoded->pixels, opaque.pixels);
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

// The refinement's measure of change (base) is compare_images' RMS error in 8-bit levels.
TEST(ChangeInLevels, IsTheRmsDifferenceOverRgbInLevels) {
    const base::ImageRgba8 before = shaded_image(40, 30);
    base::ImageRgba8 after = before;
    for (std::size_t i = 0; i < after.pixels.size(); i += 7) {
        after.pixels[i] = static_cast<std::uint8_t>(after.pixels[i] ^ 0x2A);
    }
    const auto change = base::change_in_levels(before, after);
    ASSERT_TRUE(change.ok()) << change.error().to_string();
    const auto difference = compare_images(base::to_rgba_f(before), base::to_rgba_f(after));
    ASSERT_TRUE(difference.ok());
    EXPECT_NEAR(*change, difference->rms_error * 255.0, 1e-3);
    EXPECT_GT(*change, 1.0);
    EXPECT_EQ(*base::change_in_levels(before, before), 0.0);
    EXPECT_EQ(base::change_in_levels(before, base::ImageRgba8(40, 31)).error().code,
              base::ErrorCode::size_mismatch);
}

}  // namespace
}  // namespace penumbra::encode
