#pragma once

#include <penumbra/base/image.hpp>
#include <penumbra/gpu/objects.hpp>

#include <span>

namespace penumbra::render {

// The RGBA8 image a frame ends in, rows top to bottom, re-created only when the size changes.
// Compute passes write it as image unit 0; fragment passes draw into its framebuffer.
class FrameTarget {
public:
    void ensure(int width, int height);

    [[nodiscard]] GLuint texture() const { return texture_.name(); }

    [[nodiscard]] GLuint framebuffer() const { return framebuffer_.name(); }

    void read_back(base::ImageRgba8& image) const;

private:
    gpu::Texture texture_;
    gpu::Framebuffer framebuffer_;
    int width_ = 0;
    int height_ = 0;
};

// A size x size single-channel light-space image (rows bottom-up, as GL stores them) as a grey
// picture, top row first, white where the light is unattenuated: the insets of the paper's figures.
base::ImageRgba8 transmittance_image(std::span<const float> values, int size);

}  // namespace penumbra::render
