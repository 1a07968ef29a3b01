#pragma once

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>

namespace penumbra::encode {

// Differences over the RGB channels, values in [0, 1]. PSNR is in dB with peak 1 (infinite for
// identical images).
struct ImageDifference {
    double mean_error = 0.0;
    double rms_error = 0.0;
    double psnr = 0.0;
    double max_error = 0.0;
};

base::Result<ImageDifference> compare_images(const base::ImageRgbaF& a, const base::ImageRgbaF& b);

}  // namespace penumbra::encode
