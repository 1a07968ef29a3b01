#include <penumbra/base/image.hpp>

#include <gtest/gtest.h>

#include <limits>

namespace penumbra::base {
namespace {

TEST(Image, PasteCopiesAPartInPlaceAndLeavesOutWhatFallsOutside) {
    ImageRgba8 into(4, 3);
    ImageRgba8 part(2, 2);
    for (std::size_t i = 0; i < part.pixels.size(); ++i) {
        part.pixels[i] = static_cast<std::uint8_t>(i + 1);
    }
    paste(into, part, 3, 2);  // only its top-left pixel lands inside
    EXPECT_EQ(into.pixel(3, 2)[0], 1);
    EXPECT_EQ(into.pixel(3, 2)[3], 4);
    paste(into, part, -1, 0);  // its right column lands in column 0
    EXPECT_EQ(into.pixel(0, 0)[0], 5);
    EXPECT_EQ(into.pixel(0, 1)[0], 13);
    EXPECT_EQ(into.pixel(1, 0)[0], 0);
    paste(into, part, 10, 10);  // wholly outside: nothing
    std::size_t written = 0;
    for (const std::uint8_t byte : into.pixels) {
        written += byte != 0 ? 1 : 0;
    }
    EXPECT_EQ(written, 12u);
}

TEST(Image, ToRgba8RoundsClampsAndMapsNanToZero) {
    ImageRgbaF f(2, 1);
    const float values[8] = {0.0f, 1.0f, 0.5f, -3.0f, 7.0f, std::numeric_limits<float>::quiet_NaN(),
                             0.2f, 1.0f};
    std::copy(std::begin(values), std::end(values), f.pixels.begin());
    const ImageRgba8 b = to_rgba8(f);
    EXPECT_EQ(b.pixel(0, 0)[0], 0);
    EXPECT_EQ(b.pixel(0, 0)[1], 255);
    EXPECT_EQ(b.pixel(0, 0)[2], 128);
    EXPECT_EQ(b.pixel(0, 0)[3], 0);
    EXPECT_EQ(b.pixel(1, 0)[0], 255);
    EXPECT_EQ(b.pixel(1, 0)[1], 0);
    EXPECT_EQ(b.pixel(1, 0)[2], 51);
}

}  // namespace
}  // namespace penumbra::base
