#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "penumbra/imageio/compare.hpp"

namespace penumbra::imageio {
namespace {

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

}  // namespace penumbra::imageio
