#include <penumbra/base/image.hpp>

#include <gtest/gtest.h>

#include <limits>

namespace penumbra::base {
namespace {

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
