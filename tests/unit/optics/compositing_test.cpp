#include <penumbra/optics/compositing.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace penumbra::optics {
namespace {

TEST(OpacityCorrection, IsIdentityAtTheUnitDistance) {
    EXPECT_DOUBLE_EQ(corrected_opacity(0.3, 0.01, 0.01), 0.3);
}

TEST(OpacityCorrection, TwoHalfStepsTransmitLikeOneFullStep) {
    const double half = corrected_opacity(0.3, 0.005, 0.01);
    EXPECT_NEAR((1.0 - half) * (1.0 - half), 1.0 - 0.3, 1e-15);
}

TEST(OpacityCorrection, KeepsOpaqueAndTransparentFixed) {
    EXPECT_DOUBLE_EQ(corrected_opacity(1.0, 0.37, 0.01), 1.0);
    EXPECT_DOUBLE_EQ(corrected_opacity(0.0, 0.37, 0.01), 0.0);
    EXPECT_DOUBLE_EQ(corrected_opacity(1.7, 0.01, 0.01), 1.0);  // clamped input
}

TEST(ExtinctionCompositing, TransmitsExponentially) {
    const double alpha = extinction_opacity(0.5, 0.02, 0.01);
    EXPECT_NEAR(1.0 - alpha, std::exp(-0.5 / 0.01 * 0.02), 1e-15);
    EXPECT_LT(extinction_opacity(1.0, 0.01, 0.01), 1.0);  // even full opacity transmits a little
}

TEST(Compositing, FrontToBackOverAccumulatesPremultiplied) {
    glm::dvec4 dst(0.0);
    composite_front_to_back(dst, glm::dvec3(1.0, 0.0, 0.0), 0.5);
    composite_front_to_back(dst, glm::dvec3(0.0, 1.0, 0.0), 0.5);
    EXPECT_DOUBLE_EQ(dst.r, 0.5);
    EXPECT_DOUBLE_EQ(dst.g, 0.25);
    EXPECT_DOUBLE_EQ(dst.a, 0.75);
}

}  // namespace
}  // namespace penumbra::optics
