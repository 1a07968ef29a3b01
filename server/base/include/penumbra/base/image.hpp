#pragma once

#include <penumbra/base/result.hpp>

#include <cstdint>
#include <vector>

namespace penumbra::base {

// An 8-bit RGBA image, rows stored top to bottom (the order image files use).
struct ImageRgba8 {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> pixels;  // width * height * 4

    ImageRgba8() = default;

    ImageRgba8(int w, int h);

    [[nodiscard]] const std::uint8_t* pixel(int x, int y) const {
        return &pixels[(static_cast<std::size_t>(y) * width + x) * 4];
    }

    std::uint8_t* pixel(int x, int y) {
        return &pixels[(static_cast<std::size_t>(y) * width + x) * 4];
    }
};

// A float RGBA image (linear values, normally in [0,1]), rows top to bottom. The CPU reference
// renders into this so its precision is not lost before a comparison.
struct ImageRgbaF {
    int width = 0;
    int height = 0;
    std::vector<float> pixels;  // width * height * 4

    ImageRgbaF() = default;

    ImageRgbaF(int w, int h);

    [[nodiscard]] const float* pixel(int x, int y) const {
        return &pixels[(static_cast<std::size_t>(y) * width + x) * 4];
    }

    float* pixel(int x, int y) { return &pixels[(static_cast<std::size_t>(y) * width + x) * 4]; }
};

// Copies `part` into `into` with its top-left pixel at (x, y); what falls outside `into` is left
// out (the tiles of a tiled render put together).
void paste(ImageRgba8& into, const ImageRgba8& part, int x, int y);

// Rounds to 8 bits the way a UNORM8 framebuffer does (clamp, then round to nearest).
ImageRgba8 to_rgba8(const ImageRgbaF& image);

ImageRgbaF to_rgba_f(const ImageRgba8& image);

// How much an 8-bit frame changed from `before` to `after`: the RMS difference over the RGB
// channels, in 8-bit levels (what ends a still's refinement), computed on the bytes themselves
// (it runs on the frame path, after every refinement step). Errors: size_mismatch.
Result<double> change_in_levels(const ImageRgba8& before, const ImageRgba8& after);

}  // namespace penumbra::base
