// Gradients from the precomputed texture of per-voxel differences shade like central differences
// inside the volume, and the texture is built once per volume.

#include "synthetic_volumes.hpp"

#include <penumbra/imageio/compare.hpp>
#include <penumbra/render/renderer.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace penumbra::render {
namespace {

TEST(GradientSource, ParsesItsCommandLineNames) {
    EXPECT_EQ(parse_gradient_source("automatic"), GradientSource::automatic);
    EXPECT_EQ(parse_gradient_source("central"), GradientSource::central_differences);
    EXPECT_EQ(parse_gradient_source("texture"), GradientSource::texture);
    EXPECT_FALSE(parse_gradient_source("central_differences").has_value());
    EXPECT_FALSE(parse_gradient_source("").has_value());
}

struct Rendered {
    std::vector<Frame> frames;
};

// Renders `requests` in a renderer of its own (one GL context at a time on this thread).
Rendered render_all(GradientSource source, const std::vector<scene::FrameRequest>& requests) {
    RendererOptions options;
    options.gradients = source;
    auto renderer = Renderer::create(options);
    EXPECT_TRUE(renderer.ok());
    Rendered out;
    if (!renderer.ok()) {
        return out;
    }
    EXPECT_TRUE(
            (*renderer)
                    ->set_volume(std::make_shared<const volume::Volume>(test::radial_volume(32)))
                    .ok());
    for (const auto& request : requests) {
        auto frame = (*renderer)->render(request);
        EXPECT_TRUE(frame.ok()) << frame.error().to_string();
        out.frames.push_back(frame.ok() ? std::move(frame.value()) : Frame{});
    }
    return out;
}

int builds(const Frame& frame) {
    return static_cast<int>(
            std::count_if(frame.report.passes.begin(), frame.report.passes.end(),
                          [](const PassTiming& p) { return p.name == "build_gradients"; }));
}

TEST(GradientTextureTest, ShadesLikeCentralDifferencesInsideTheVolume) {
    scene::FrameRequest request;
    request.camera = scene::orbit_camera(30.0, 20.0, 2.4);
    request.light.direction = scene::direction_from_angles(-60.0, 35.0);
    request.settings.mode = scene::Mode::phong;
    request.settings.width = 64;
    request.settings.height = 64;
    request.settings.sample_distance = 1.0 / 128.0;
    // Transparent near the box faces (value 0 there), so only the smooth inside is shaded.
    request.transfer_function = {"shell",
                                 {{0.0, {1.0, 0.8, 0.6}}, {1.0, {1.0, 1.0, 1.0}}},
                                 {{0.0, 0.0}, {0.4, 0.0}, {0.45, 0.8}, {1.0, 0.8}}};
    scene::FrameRequest moved = request;
    moved.camera = scene::orbit_camera(60.0, 10.0, 2.4);

    const Rendered central = render_all(GradientSource::central_differences, {request});
    const Rendered texture = render_all(GradientSource::texture, {request, moved});
    ASSERT_EQ(central.frames.size(), 1u);
    ASSERT_EQ(texture.frames.size(), 2u);
    EXPECT_EQ(builds(central.frames[0]), 0);
    EXPECT_EQ(builds(texture.frames[0]), 1);
    EXPECT_EQ(builds(texture.frames[1]), 0) << "built once per volume, not per frame";
    auto difference = imageio::compare_images(base::to_rgba_f(central.frames[0].image),
                                              base::to_rgba_f(texture.frames[0].image));
    ASSERT_TRUE(difference.ok());
    // Within the smooth inside the two agree to a level of 8 bits or so.
    EXPECT_GT(difference->psnr, 60.0);
    EXPECT_LE(difference->max_error, 2.0 / 255.0);
    const base::ImageRgba8& image = texture.frames[0].image;
    int lit = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            lit += image.pixel(x, y)[0] > 0 ? 1 : 0;
        }
    }
    EXPECT_GT(lit, 400) << "the shell should fill much of the image";
}

}  // namespace
}  // namespace penumbra::render
