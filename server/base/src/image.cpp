#include "penumbra/base/image.hpp"

#include <algorithm>
#include <cmath>

namespace penumbra::base {

ImageRgba8::ImageRgba8(int w, int h)
    : width(w)
    , height(h)
    , pixels(static_cast<std::size_t>(w) * h * 4, 0) {}

ImageRgbaF::ImageRgbaF(int w, int h)
    : width(w)
    , height(h)
    , pixels(static_cast<std::size_t>(w) * h * 4, 0.0f) {}

ImageRgba8 to_rgba8(const ImageRgbaF& image) {
    ImageRgba8 out(image.width, image.height);
    std::transform(image.pixels.begin(), image.pixels.end(), out.pixels.begin(), [](float v) {
        const float clamped = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
        return static_cast<std::uint8_t>(std::lround(clamped * 255.0f));
    });
    return out;
}

ImageRgbaF to_rgba_f(const ImageRgba8& image) {
    ImageRgbaF out(image.width, image.height);
    std::transform(image.pixels.begin(), image.pixels.end(), out.pixels.begin(),
                   [](std::uint8_t v) { return static_cast<float>(v) / 255.0f; });
    return out;
}

}  // namespace penumbra::base
