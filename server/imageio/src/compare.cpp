#include "penumbra/imageio/compare.hpp"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <cstdint>
#include <limits>
#include <string>

namespace penumbra::imageio {
namespace {

OIIO::ImageBuf wrap_rgb(const base::ImageRgbaF& image) {
    OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf rgba(spec, const_cast<float*>(image.pixels.data()));
    // Compare colour only: frames are opaque, alpha carries no information.
    return OIIO::ImageBufAlgo::channels(rgba, 3, {});
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

}  // namespace penumbra::imageio
