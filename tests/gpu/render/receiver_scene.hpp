#pragma once

// The receiver scene that the cut and label tests light: shadow_test's volume (a receiver column
// lit along -x, half of it behind a slab; test::shadow_scene) seen from +z, and where its parts
// land in the 64x64 image.

#include <penumbra/render/frame.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <algorithm>

namespace penumbra::test {

// The scene's frame in `mode`: 64x64, extinction compositing, the light along -x, no ambient.
inline scene::FrameRequest receiver_scene(scene::Mode mode) {
    scene::FrameRequest request;
    request.camera.eye = {0.0, 0.0, 3.0};
    request.camera.target = {0.0, 0.0, 0.0};
    request.camera.up = {0.0, 1.0, 0.0};
    request.light.direction = {1.0, 0.0, 0.0};  // toward the light: light travels along -x
    request.light.ambient = 0.0;
    request.settings.shading.diffuse = 1.0;
    request.settings.mode = mode;
    request.settings.width = 64;
    request.settings.height = 64;
    request.settings.compositing = scene::Compositing::extinction;
    request.settings.sample_distance = 1.0 / 128.0;
    request.settings.light_buffer.slices = 256;
    request.settings.light_buffer.resolution = 64;
    request.transfer_function = {
            "slab", {{0.0, {1.0, 1.0, 1.0}}}, {{0.0, 0.0}, {0.5, 0.03}, {1.0, 0.004}}};
    return request;
}

// The mean red of the receiver's middle columns (world x = -0.25 projects to column 22) over
// image rows row0..row1: world y = -0.3, behind the slab, is row 44, y = +0.3 row 20.
inline double receiver_red(const render::Frame& frame, int row0, int row1) {
    double sum = 0.0;
    int count = 0;
    for (int y = row0; y <= row1; ++y) {
        for (int x = 20; x <= 24; ++x) {
            sum += frame.image.pixel(x, y)[0];
            ++count;
        }
    }
    return sum / count;
}

// The brightest red where the slab shows (world x 0.25..0.375, y < 0: columns 43..46, rows 36..60).
inline double brightest_on_slab(const render::Frame& frame) {
    double brightest = 0.0;
    for (int y = 36; y <= 60; ++y) {
        for (int x = 43; x <= 46; ++x) {
            brightest = std::max(brightest, static_cast<double>(frame.image.pixel(x, y)[0]));
        }
    }
    return brightest;
}

}  // namespace penumbra::test
