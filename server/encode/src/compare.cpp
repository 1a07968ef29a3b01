#include "penumbra/encode/compare.hpp"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace penumbra::encode {
namespace {

OIIO::ImageBuf wrap_rgb(const base::ImageRgbaF& image) {
    OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf rgba(spec, const_cast<float*>(image.pixels.data()));
    // Compare colour only: frames are opaque, alpha carries no information.
    return OIIO::ImageBufAlgo::channels(rgba, 3, {});
}

using Kernel = std::array<double, SsimParameters::window>;

// The normalised 1-D Gaussian; the 2-D window is its outer product, so filtering is separable.
Kernel gaussian_kernel() {
    Kernel kernel{};
    constexpr int half = SsimParameters::window / 2;
    double sum = 0.0;
    for (int i = 0; i < SsimParameters::window; ++i) {
        const double x = static_cast<double>(i - half);
        kernel[static_cast<std::size_t>(i)] =
                std::exp(-x * x / (2.0 * SsimParameters::sigma * SsimParameters::sigma));
        sum += kernel[static_cast<std::size_t>(i)];
    }
    for (double& k : kernel) {
        k /= sum;
    }
    return kernel;
}

std::vector<double> luma(const base::ImageRgbaF& image) {
    std::vector<double> y(static_cast<std::size_t>(image.width) *
                          static_cast<std::size_t>(image.height));
    for (std::size_t i = 0; i < y.size(); ++i) {
        const float* p = &image.pixels[i * 4];
        y[i] = 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
    }
    return y;
}

// Gaussian-weighted means of `values` at every window position wholly inside the image: first
// along rows, then along columns. Result is (width - 10) x (height - 10).
std::vector<double> filter_valid(const std::vector<double>& values, int width, int height,
                                 const Kernel& kernel) {
    constexpr int side = SsimParameters::window;
    const int out_w = width - side + 1;
    const int out_h = height - side + 1;
    std::vector<double> rows(static_cast<std::size_t>(out_w) * static_cast<std::size_t>(height));
    for (int y = 0; y < height; ++y) {
        const double* in = &values[static_cast<std::size_t>(y) * static_cast<std::size_t>(width)];
        double* out = &rows[static_cast<std::size_t>(y) * static_cast<std::size_t>(out_w)];
        for (int x = 0; x < out_w; ++x) {
            double sum = 0.0;
            for (int k = 0; k < side; ++k) {
                sum += kernel[static_cast<std::size_t>(k)] * in[x + k];
            }
            out[x] = sum;
        }
    }
    std::vector<double> result(static_cast<std::size_t>(out_w) * static_cast<std::size_t>(out_h));
    for (int y = 0; y < out_h; ++y) {
        for (int x = 0; x < out_w; ++x) {
            double sum = 0.0;
            for (int k = 0; k < side; ++k) {
                sum += kernel[static_cast<std::size_t>(k)] *
                       rows[static_cast<std::size_t>(y + k) * static_cast<std::size_t>(out_w) +
                            static_cast<std::size_t>(x)];
            }
            result[static_cast<std::size_t>(y) * static_cast<std::size_t>(out_w) +
                   static_cast<std::size_t>(x)] = sum;
        }
    }
    return result;
}

}  // namespace

base::Result<ImageDifference> compare_images(const base::ImageRgbaF& a, const base::ImageRgbaF& b) {
    if (a.width != b.width || a.height != b.height) {
        return base::make_error(base::ErrorCode::size_mismatch, "images differ in size", "compare");
    }
    const OIIO::ImageBuf rgb_a = wrap_rgb(a);
    const OIIO::ImageBuf rgb_b = wrap_rgb(b);
    const auto result = OIIO::ImageBufAlgo::compare(rgb_a, rgb_b, 1.0f, 1.0f);
    ImageDifference difference;
    difference.mean_error = result.meanerror;
    difference.rms_error = result.rms_error;
    difference.max_error = result.maxerror;
    difference.psnr =
            result.rms_error > 0.0 ? result.PSNR : std::numeric_limits<double>::infinity();
    return difference;
}

base::Result<double> change_in_levels(const base::ImageRgba8& before,
                                      const base::ImageRgba8& after) {
    // On the frame path (every refinement step): the bytes as they are, no float copies.
    if (before.width != after.width || before.height != after.height) {
        return base::make_error(base::ErrorCode::size_mismatch, "images differ in size",
                                "change_in_levels");
    }
    std::uint64_t squares = 0;
    for (std::size_t i = 0; i < before.pixels.size(); i += 4) {
        for (std::size_t c = 0; c < 3; ++c) {
            const int d = int{before.pixels[i + c]} - int{after.pixels[i + c]};
            squares += static_cast<std::uint64_t>(d * d);
        }
    }
    const std::size_t values = before.pixels.size() / 4 * 3;
    return values == 0 ? 0.0
                       : std::sqrt(static_cast<double>(squares) / static_cast<double>(values));
}

base::Result<base::ImageRgba8> stretched(const base::ImageRgba8& image, int width, int height) {
    if (width < 1 || height < 1 || image.width < 1 || image.height < 1) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "cannot stretch " + std::to_string(image.width) + "x" +
                                        std::to_string(image.height) + " to " +
                                        std::to_string(width) + "x" + std::to_string(height),
                                "stretched");
    }
    const OIIO::ImageSpec from(image.width, image.height, 4, OIIO::TypeDesc::UINT8);
    const OIIO::ImageBuf source(from, const_cast<std::uint8_t*>(image.pixels.data()));
    base::ImageRgba8 result(width, height);
    OIIO::ImageBuf target(OIIO::ImageSpec(width, height, 4, OIIO::TypeDesc::UINT8),
                          result.pixels.data());
    if (!OIIO::ImageBufAlgo::resample(target, source, /*interpolate=*/true)) {
        return base::make_error(base::ErrorCode::internal_error, target.geterror(), "stretched");
    }
    return result;
}

base::Result<double> ssim(const base::ImageRgbaF& a, const base::ImageRgbaF& b) {
    if (a.width != b.width || a.height != b.height) {
        return base::make_error(base::ErrorCode::size_mismatch, "images differ in size", "ssim");
    }
    constexpr int side = SsimParameters::window;
    if (a.width < side || a.height < side) {
        return base::make_error(base::ErrorCode::image_too_small,
                                std::to_string(a.width) + "x" + std::to_string(a.height) +
                                        " is smaller than the " + std::to_string(side) + "x" +
                                        std::to_string(side) + " SSIM window",
                                "ssim");
    }
    const int w = a.width;
    const int h = a.height;
    const Kernel kernel = gaussian_kernel();
    const std::vector<double> x = luma(a);
    const std::vector<double> y = luma(b);
    std::vector<double> xx(x.size());
    std::vector<double> yy(x.size());
    std::vector<double> xy(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
        xx[i] = x[i] * x[i];
        yy[i] = y[i] * y[i];
        xy[i] = x[i] * y[i];
    }
    const std::vector<double> mu_x = filter_valid(x, w, h, kernel);
    const std::vector<double> mu_y = filter_valid(y, w, h, kernel);
    const std::vector<double> e_xx = filter_valid(xx, w, h, kernel);
    const std::vector<double> e_yy = filter_valid(yy, w, h, kernel);
    const std::vector<double> e_xy = filter_valid(xy, w, h, kernel);

    constexpr double c1 = (SsimParameters::k1 * SsimParameters::peak) *
                          (SsimParameters::k1 * SsimParameters::peak);
    constexpr double c2 = (SsimParameters::k2 * SsimParameters::peak) *
                          (SsimParameters::k2 * SsimParameters::peak);
    double sum = 0.0;
    for (std::size_t i = 0; i < mu_x.size(); ++i) {
        const double mx = mu_x[i];
        const double my = mu_y[i];
        // E[x^2] - mu^2 can come out a hair below zero in floating point for flat windows.
        const double var_x = std::max(e_xx[i] - mx * mx, 0.0);
        const double var_y = std::max(e_yy[i] - my * my, 0.0);
        const double cov = e_xy[i] - mx * my;
        sum += ((2.0 * mx * my + c1) * (2.0 * cov + c2)) /
               ((mx * mx + my * my + c1) * (var_x + var_y + c2));
    }
    return sum / static_cast<double>(mu_x.size());
}

}  // namespace penumbra::encode
