#pragma once

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>

namespace penumbra::imageio {

// Comparing images: OpenImageIO's for differences and resampling (a build without OpenImageIO
// returns image_io_unavailable from those, imageio.hpp), SSIM written here (OpenImageIO has none).

// Differences over the RGB channels, values in [0, 1]. PSNR is in dB with peak 1 (infinite for
// identical images).
struct ImageDifference {
    double mean_error = 0.0;
    double rms_error = 0.0;
    double psnr = 0.0;
    double max_error = 0.0;
};

base::Result<ImageDifference> compare_images(const base::ImageRgbaF& a, const base::ImageRgbaF& b);

// The image stretched (or shrunk) to width x height by bilinear interpolation at pixel centres, as
// a browser draws a smaller frame on a larger canvas: how an interactive frame, rendered at half
// the size, is seen. Errors: invalid_argument for a side below 1.
base::Result<base::ImageRgba8> stretched(const base::ImageRgba8& image, int width, int height);

// The SSIM parameters of Wang, Bovik, Sheikh & Simoncelli, "Image quality assessment: from error
// visibility to structural similarity" (IEEE TIP 2004), the ones their reference code and most
// published SSIM values use.
struct SsimParameters {
    static constexpr int window = 11;     // Gaussian window side, pixels
    static constexpr double sigma = 1.5;  // its standard deviation, pixels
    static constexpr double k1 = 0.01;
    static constexpr double k2 = 0.03;
    static constexpr double peak = 1.0;  // L, the dynamic range of the values
};

// Mean structural similarity of two images of the same size, 1 for identical images, in [-1, 1].
// Computed on Rec. 601 luma (Y = 0.299 R + 0.587 G + 0.114 B of the values as stored, as MATLAB's
// rgb2gray and so Wang et al.'s published numbers do) with the parameters above: the SSIM map at
// every position where the 11 x 11 window lies wholly inside the image (Wang et al.'s "valid"
// filtering, no padding that would invent structure at the borders), then averaged. Weighted
// statistics use the biased (population) variance, as the paper does. Alpha is ignored.
// Errors: size_mismatch, image_too_small (a side below the window's 11 pixels).
base::Result<double> ssim(const base::ImageRgbaF& a, const base::ImageRgbaF& b);

}  // namespace penumbra::imageio
