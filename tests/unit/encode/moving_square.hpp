#pragma once

// Frames for the movie and stream tests: a colour ramp with a square moving across it, and how
// near a decoded frame is to one.

#include <penumbra/base/image.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace penumbra::encode {

// Frame k: the square `step` pixels a frame further right.
inline base::ImageRgba8 moving_square(int width, int height, int k, int step = 3) {
    base::ImageRgba8 image(width, height);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            std::uint8_t* p = image.pixel(x, y);
            const bool square = x >= 4 + step * k && x < 20 + step * k && y >= 12 && y < 28;
            p[0] = square ? 240 : static_cast<std::uint8_t>((4 * x) & 255);
            p[1] = square ? 200 : static_cast<std::uint8_t>((5 * y) & 255);
            p[2] = square ? 40 : 120;
            p[3] = 255;
        }
    }
    return image;
}

// PSNR over the colour channels, dB.
inline double psnr(const base::ImageRgba8& a, const base::ImageRgba8& b) {
    double squared = 0.0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        if (i % 4 != 3) {
            const double d = double(a.pixels[i]) - double(b.pixels[i]);
            squared += d * d;
            ++count;
        }
    }
    return 10.0 * std::log10(255.0 * 255.0 / std::max(1e-9, squared / double(count)));
}

}  // namespace penumbra::encode
