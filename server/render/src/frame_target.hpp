#pragma once

#include <penumbra/base/image.hpp>
#include <penumbra/gpu/objects.hpp>

#include <span>

namespace penumbra::render {

// The image a frame ends in, rows top to bottom, re-created only when the size changes. Compute
// passes write it as image unit 0 (format `image_format`); fragment passes draw into its
// framebuffer. It holds float colour so that progressive stills average the unrounded frames;
// frames are read back as 8 bits (Renderer::complete), as an RGBA8 target would have held them.
class FrameTarget {
public:
    static constexpr GLenum image_format = GL_RGBA32F;

    void ensure(int width, int height);

    [[nodiscard]] const gpu::Texture& texture() const { return texture_; }

    [[nodiscard]] const gpu::Framebuffer& framebuffer() const { return framebuffer_; }

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
