// An image rendered in tiles (scene::Tile, each tile a frame of its own) is the image rendered
// whole: the same rays, the same jitter, the same refinement, in every mode, so that a picture
// larger than one frame may be can be exported without seams.

#include "synthetic_volumes.hpp"

#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/mode.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace penumbra::render {
namespace {

class TileTest : public ::testing::Test {
protected:
    void SetUp() override {
        auto created = Renderer::create();
        ASSERT_TRUE(created.ok()) << created.error().to_string();
        renderer_ = std::move(created.value());
        // A ball in front of a slab, lit from the side: shadows, gradients and edges in every
        // tile.
        ASSERT_TRUE(
                renderer_
                        ->set_volume(std::make_shared<const volume::Volume>(test::shadow_scene(40)))
                        .ok());
    }

    static scene::FrameRequest request(scene::Mode mode) {
        scene::FrameRequest r;
        r.camera = scene::orbit_camera(30.0, 20.0, 2.0);
        r.light.direction = scene::direction_from_angles(-60.0, 35.0);
        r.transfer_function = {"ramp",
                               {{0.0, {0.9, 0.6, 0.4}}, {1.0, {1.0, 1.0, 0.9}}},
                               {{0.0, 0.0}, {0.3, 0.0}, {0.6, 0.5}, {1.0, 0.8}}};
        scene::RenderSettings& s = r.settings;
        s.mode = mode;
        s.phong = true;
        s.jitter = scene::is_ray_cast(mode);
        s.width = 96;
        s.height = 72;
        s.sample_distance = 1.0 / 64.0;
        s.light_buffer.slices = 32;
        s.light_buffer.resolution = 64;
        return r;
    }

    base::ImageRgba8 render(const scene::FrameRequest& r) {
        auto frame = renderer_->render(r);
        EXPECT_TRUE(frame.ok()) << frame.error().to_string();
        return frame.ok() ? std::move(frame->image) : base::ImageRgba8{};
    }

    base::ImageRgba8 render_tiled(const std::vector<scene::FrameRequest>& tiles, int width,
                                  int height) {
        base::ImageRgba8 image(width, height);
        for (const scene::FrameRequest& tile : tiles) {
            base::paste(image, render(tile), tile.tile.x, tile.tile.y);
        }
        return image;
    }

    // The largest difference of a channel, in 8-bit levels, and how many channels differ.
    struct Difference {
        int largest = 0;
        std::size_t count = 0;
    };

    static Difference difference(const base::ImageRgba8& a, const base::ImageRgba8& b) {
        Difference d;
        EXPECT_EQ(a.pixels.size(), b.pixels.size());
        for (std::size_t i = 0; i < std::min(a.pixels.size(), b.pixels.size()); ++i) {
            const int levels = std::abs(int{a.pixels[i]} - int{b.pixels[i]});
            d.largest = std::max(d.largest, levels);
            d.count += levels > 0 ? 1 : 0;
        }
        return d;
    }

    std::unique_ptr<Renderer> renderer_;
};

TEST_F(TileTest, AnImageRenderedInTilesIsTheImageRenderedWholeInEveryMode) {
    for (const scene::ModeInfo& info : scene::modes()) {
        SCOPED_TRACE(info.name);
        const scene::FrameRequest whole = request(info.mode);
        // 40-pixel tiles of 96x72: three columns and two rows, the last of each narrower.
        const std::vector<scene::FrameRequest> tiles = scene::image_tiles(whole, 40);
        ASSERT_EQ(tiles.size(), 6u);
        const base::ImageRgba8 one = render(whole);
        const Difference d = difference(render_tiled(tiles, 96, 72), one);
        // Float rounding of the same rays (and, rasterised, of the same slices) at most: on
        // llvmpipe one level in one or two channels of 27648.
        EXPECT_LE(d.largest, 1);
        EXPECT_LE(d.count, one.pixels.size() / 500);

        // Tiles that each showed the whole view, squeezed, would be nothing like it.
        std::vector<scene::FrameRequest> squeezed = tiles;
        for (scene::FrameRequest& tile : squeezed) {
            tile.tile = {};
        }
        EXPECT_GT(difference(render_tiled(squeezed, 96, 72), one).largest, 40);
    }
}

TEST_F(TileTest, ATilesRefinementStepsRefineItAsTheWholeImagesDo) {
    scene::FrameRequest whole = request(scene::Mode::sbrc);
    whole.refinement = {true, 0};
    const std::vector<scene::FrameRequest> tiles = scene::image_tiles(whole, 48);
    ASSERT_EQ(tiles.size(), 4u);
    // The still and two steps of the whole image, then of each tile in turn (each tile's mean is
    // its own, kept beside the others').
    base::ImageRgba8 one;
    for (int step = 0; step <= 2; ++step) {
        scene::FrameRequest r = step == 0 ? whole : scene::refinement_step_request(whole, step);
        one = render(r);
    }
    base::ImageRgba8 tiled(96, 72);
    for (const scene::FrameRequest& tile : tiles) {
        base::ImageRgba8 refined;
        for (int step = 0; step <= 2; ++step) {
            refined = render(step == 0 ? tile : scene::refinement_step_request(tile, step));
        }
        base::paste(tiled, refined, tile.tile.x, tile.tile.y);
    }
    const Difference d = difference(tiled, one);
    EXPECT_LE(d.largest, 1);
    EXPECT_LE(d.count, one.pixels.size() / 500);
}

TEST_F(TileTest, ATileOutsideItsImageIsRefused) {
    scene::FrameRequest tile = request(scene::Mode::dvr);
    tile.tile = {64, 64, 0, 0};  // a 96x72 frame cannot be a tile of a 64x64 image
    auto frame = renderer_->render(tile);
    ASSERT_FALSE(frame.ok());
    EXPECT_EQ(frame.error().where, "tile");
}

}  // namespace
}  // namespace penumbra::render
