#include "penumbra/encode/compare.hpp"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <limits>

namespace penumbra::encode {
namespace {

OIIO::ImageBuf wrap_rgb(const base::ImageRgbaF& image) {
    OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf rgba(spec, const_cast<float*>(image.pixels.data()));
    // Compare colour only: frames are opaque, alpha carries no information.
    return OIIO::ImageBufAlgo::channels(rgba, 3, {});
}

}  // namespace

base::Result<ImageDifference> compare_images(const base::ImageRgbaF& a,
                                             const base::ImageRgbaF& b) {
    if (a.width != b.width || a.height != b.height) {
        return base::make_error("size_mismatch", "images differ in size", "compare");
    }
    const OIIO::ImageBuf rgb_a = wrap_rgb(a);
    const OIIO::ImageBuf rgb_b = wrap_rgb(b);
    const auto result = OIIO::ImageBufAlgo::compare(rgb_a, rgb_b, 1.0f, 1.0f);
    ImageDifference difference;
    difference.mean_error = result.meanerror;
    difference.rms_error = result.rms_error;
    difference.max_error = result.maxerror;
    difference.psnr = result.rms_error > 0.0 ? result.PSNR : std::numeric_limits<double>::infinity();
    return difference;
}

}  // namespace penumbra::encode
