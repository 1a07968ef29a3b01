#include <penumbra/imageio/compare.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

namespace penumbra::imageio {
namespace {

constexpr double c1 = 0.01 * 0.01;  // (K1 L)^2, L = 1
constexpr double c2 = 0.03 * 0.03;  // (K2 L)^2

base::ImageRgbaF constant_image(int w, int h, float r, float g, float b) {
    base::ImageRgbaF image(w, h);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            float* p = image.pixel(x, y);
            p[0] = r;
            p[1] = g;
            p[2] = b;
            p[3] = 1.0f;
        }
    }
    return image;
}

// Grey pixels from a fixed linear congruential sequence: reproducible texture without <random>'s
// implementation-defined distributions.
base::ImageRgbaF noise_image(int w, int h, std::uint32_t seed) {
    base::ImageRgbaF image(w, h);
    std::uint32_t state = seed;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            state = state * 1664525u + 1013904223u;
            const float v = static_cast<float>(state >> 8) / static_cast<float>(1u << 24);
            float* p = image.pixel(x, y);
            p[0] = p[1] = p[2] = v;
            p[3] = 1.0f;
        }
    }
    return image;
}

TEST(Ssim, IdenticalImagesScoreOne) {
    const base::ImageRgbaF image = noise_image(40, 31, 7);
    auto same = ssim(image, image);
    ASSERT_TRUE(same.ok()) << same.error().to_string();
    EXPECT_NEAR(*same, 1.0, 1e-12);
}

// Flat images have no variance: only the luminance term (2 mu_x mu_y + C1) / (mu_x^2 + mu_y^2 + C1)
// remains, the same at every window.
TEST(Ssim, ConstantOffsetScoresTheLuminanceTerm) {
    const base::ImageRgbaF a = constant_image(16, 16, 0.5f, 0.5f, 0.5f);
    const base::ImageRgbaF b = constant_image(16, 16, 0.6f, 0.6f, 0.6f);
    auto score = ssim(a, b);
    ASSERT_TRUE(score.ok());
    // (2 * 0.5 * 0.6 + C1) / (0.25 + 0.36 + C1) = 0.6001 / 0.6101
    EXPECT_NEAR(*score, 0.9836092443861661, 1e-6);
    EXPECT_NEAR(*score, (2.0 * 0.5 * 0.6 + c1) / (0.25 + 0.36 + c1), 1e-6);
}

// An offset added to texture leaves the contrast-structure term at 1 and lowers the score.
TEST(Ssim, OffsetOnTextureScoresBelowOneAndIsSymmetric) {
    const base::ImageRgbaF a = noise_image(24, 24, 3);
    base::ImageRgbaF b = a;
    for (std::size_t i = 0; i < b.pixels.size(); ++i) {
        if (i % 4 != 3) {
            b.pixels[i] += 0.1f;
        }
    }
    const double ab = ssim(a, b).value();
    const double ba = ssim(b, a).value();
    EXPECT_LT(ab, 1.0);
    EXPECT_GT(ab, 0.9);
    EXPECT_NEAR(ab, ba, 1e-12);
}

// Luminance is Rec. 601 luma: pure red is Y = 0.299, pure green Y = 0.587.
TEST(Ssim, UsesRec601Luma) {
    const base::ImageRgbaF red = constant_image(11, 11, 1.0f, 0.0f, 0.0f);
    const base::ImageRgbaF green = constant_image(11, 11, 0.0f, 1.0f, 0.0f);
    auto score = ssim(red, green);
    ASSERT_TRUE(score.ok());
    EXPECT_NEAR(*score, 0.8089156126891975, 1e-6);
}

// One 11 x 11 window worked by hand. x = 0.5 + 0.2 s, y = 0.5 - 0.2 s with s = sign(column - 5):
// the window is symmetric, so mu_x = mu_y = 0.5 and the luminance term is 1. Every pixel off the
// centre column deviates by 0.2; the column weights are g(k) = exp(-k^2 / 4.5) / sum, and the
// centre column's weight is 1 / sum_{k=-5..5} exp(-k^2 / 4.5) = 1 / 3.759232 = 0.266012. So
// var_x = var_y = 0.04 (1 - 0.266012) = 0.0293595, cov = -0.0293595, and
// SSIM = (-2 (0.0293595) + C2) / (2 (0.0293595) + C2) = -0.057819 / 0.059619 = -0.969808.
TEST(Ssim, HandComputedAntiCorrelatedWindow) {
    base::ImageRgbaF a(11, 11);
    base::ImageRgbaF b(11, 11);
    for (int y = 0; y < 11; ++y) {
        for (int x = 0; x < 11; ++x) {
            const float s = x < 5 ? -1.0f : x > 5 ? 1.0f : 0.0f;
            float* pa = a.pixel(x, y);
            float* pb = b.pixel(x, y);
            pa[0] = pa[1] = pa[2] = 0.5f + 0.2f * s;
            pb[0] = pb[1] = pb[2] = 0.5f - 0.2f * s;
            pa[3] = pb[3] = 1.0f;
        }
    }
    auto score = ssim(a, b);
    ASSERT_TRUE(score.ok());
    EXPECT_NEAR(*score, -0.9698083139975234, 1e-6);
}

// The separable, valid-region implementation against the definition written out directly: every
// window position, the full 2-D Gaussian, weighted means, biased variances, then the average.
TEST(Ssim, MatchesTheDefinitionComputedDirectly) {
    const int w = 19;
    const int h = 14;
    const base::ImageRgbaF a = noise_image(w, h, 11);
    base::ImageRgbaF b = noise_image(w, h, 12);
    for (std::size_t i = 0; i < b.pixels.size(); ++i) {
        b.pixels[i] = 0.6f * a.pixels[i] + 0.4f * b.pixels[i];  // partly correlated
    }
    double kernel[11][11];
    double total = 0.0;
    for (int j = 0; j < 11; ++j) {
        for (int i = 0; i < 11; ++i) {
            const double dx = i - 5;
            const double dy = j - 5;
            kernel[j][i] = std::exp(-(dx * dx + dy * dy) / (2.0 * 1.5 * 1.5));
            total += kernel[j][i];
        }
    }
    double sum = 0.0;
    int windows = 0;
    for (int oy = 0; oy + 11 <= h; ++oy) {
        for (int ox = 0; ox + 11 <= w; ++ox) {
            double mx = 0.0;
            double my = 0.0;
            for (int j = 0; j < 11; ++j) {
                for (int i = 0; i < 11; ++i) {
                    mx += kernel[j][i] / total * a.pixel(ox + i, oy + j)[0];
                    my += kernel[j][i] / total * b.pixel(ox + i, oy + j)[0];
                }
            }
            double vx = 0.0;
            double vy = 0.0;
            double cxy = 0.0;
            for (int j = 0; j < 11; ++j) {
                for (int i = 0; i < 11; ++i) {
                    const double dx = a.pixel(ox + i, oy + j)[0] - mx;
                    const double dy = b.pixel(ox + i, oy + j)[0] - my;
                    vx += kernel[j][i] / total * dx * dx;
                    vy += kernel[j][i] / total * dy * dy;
                    cxy += kernel[j][i] / total * dx * dy;
                }
            }
            sum += (2.0 * mx * my + c1) * (2.0 * cxy + c2) /
                   ((mx * mx + my * my + c1) * (vx + vy + c2));
            ++windows;
        }
    }
    EXPECT_EQ(windows, 9 * 4);
    auto score = ssim(a, b);
    ASSERT_TRUE(score.ok());
    EXPECT_NEAR(*score, sum / windows, 1e-9);
    EXPECT_GT(*score, 0.3);
    EXPECT_LT(*score, 0.99);
}

TEST(Ssim, RejectsMismatchedAndTooSmallImages) {
    EXPECT_EQ(ssim(noise_image(16, 16, 1), noise_image(16, 17, 1)).error().code,
              base::ErrorCode::size_mismatch);
    EXPECT_EQ(ssim(noise_image(10, 16, 1), noise_image(10, 16, 1)).error().code,
              base::ErrorCode::image_too_small);
}

}  // namespace
}  // namespace penumbra::imageio
