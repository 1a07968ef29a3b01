#include "penumbra/base/image.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

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

void paste(ImageRgba8& into, const ImageRgba8& part, int x, int y) {
    const int left = std::max(0, -x);
    const int right = std::min(part.width, into.width - x);
    if (left >= right) {
        return;
    }
    const auto row_bytes = static_cast<std::size_t>(right - left) * 4;
    for (int row = std::max(0, -y); row < std::min(part.height, into.height - y); ++row) {
        std::memcpy(into.pixel(x + left, y + row), part.pixel(left, row), row_bytes);
    }
}

Result<double> change_in_levels(const ImageRgba8& before, const ImageRgba8& after) {
    // On the frame path (every refinement step): the bytes as they are, no float copies.
    if (before.width != after.width || before.height != after.height) {
        return make_error(ErrorCode::size_mismatch, "images differ in size", "change_in_levels");
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

}  // namespace penumbra::base
