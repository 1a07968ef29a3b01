#include <penumbra/imageio/compare.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace penumbra::imageio {
namespace {

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

// A browser draws a half-size frame on the full canvas by bilinear interpolation at pixel
// centres: a constant stays constant, a ramp across two pixels becomes the ramp between their
// centres (clamped at the edges), and a nonsense size is refused.
TEST(Stretched, InterpolatesBetweenPixelCentresAsABrowserScales) {
    base::ImageRgba8 two(2, 1);
    for (int c = 0; c < 4; ++c) {
        two.pixels[static_cast<std::size_t>(c)] = 0;
        two.pixels[static_cast<std::size_t>(4 + c)] = 200;
    }
    auto four = stretched(two, 4, 2);
    ASSERT_TRUE(four.ok()) << four.error().to_string();
    ASSERT_EQ(four->width, 4);
    ASSERT_EQ(four->height, 2);
    // Centres 0.5, 1.5, 2.5, 3.5 of the wide image are 0.25, 0.75, 1.25, 1.75 of the narrow one,
    // whose pixel centres are 0.5 and 1.5.
    for (int y = 0; y < 2; ++y) {
        EXPECT_EQ(four->pixel(0, y)[0], 0);
        EXPECT_NEAR(four->pixel(1, y)[0], 50, 1);
        EXPECT_NEAR(four->pixel(2, y)[0], 150, 1);
        EXPECT_EQ(four->pixel(3, y)[0], 200);
    }
    base::ImageRgba8 grey(3, 3);
    std::fill(grey.pixels.begin(), grey.pixels.end(), std::uint8_t{77});
    auto large = stretched(grey, 7, 5);
    ASSERT_TRUE(large.ok());
    EXPECT_TRUE(std::all_of(large->pixels.begin(), large->pixels.end(),
                            [](std::uint8_t v) { return v == 77; }));
    EXPECT_EQ(stretched(grey, 0, 4).error().code, base::ErrorCode::invalid_argument);
    EXPECT_EQ(stretched(base::ImageRgba8{}, 4, 4).error().code, base::ErrorCode::invalid_argument);
}

}  // namespace
}  // namespace penumbra::imageio
