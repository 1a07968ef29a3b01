#pragma once

// Frames encoded by the codec libraries themselves: JPEG through libjpeg-turbo's TurboJPEG API,
// PNG through libpng. Arguments are checked by encode_image.

#include <penumbra/base/image.hpp>
#include <penumbra/base/result.hpp>
#include <penumbra/encode/encode.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace penumbra::encode {

base::Result<std::vector<std::uint8_t>> encode_jpeg(const base::ImageRgba8& image, int quality);

base::Result<std::vector<std::uint8_t>> encode_png(const base::ImageRgba8& image,
                                                   std::span<const ImageText> text = {});

}  // namespace penumbra::encode
