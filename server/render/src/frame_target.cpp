#include "frame_target.hpp"

#include <penumbra/gpu/commands.hpp>

#include <algorithm>
#include <cmath>

namespace penumbra::render {

void FrameTarget::ensure(int width, int height) {
    if (texture_ && width == width_ && height == height_) {
        return;
    }
    texture_ = gpu::create_texture_2d(image_format, width, height);
    framebuffer_ = gpu::create_framebuffer(texture_);
    width_ = width;
    height_ = height;
}

base::ImageRgba8 transmittance_image(std::span<const float> values, int size) {
    base::ImageRgba8 image(size, size);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const float v = values[static_cast<std::size_t>(size - 1 - y) * size + x];
            const auto grey =
                    static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
            std::uint8_t* p = image.pixel(x, y);
            p[0] = p[1] = p[2] = grey;
            p[3] = 255;
        }
    }
    return image;
}

}  // namespace penumbra::render
