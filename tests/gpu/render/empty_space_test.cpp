// Empty-space skipping never changes what is visible: every ray-cast mode (and half-angle
// slicing, whose light slabs skip too) gives the same image with and without it, on volumes whose
// thin features lie on the faces of the bricks, with fully transparent and fully opaque transfer
// functions, and after a TF change that makes a brick visible which was empty before.

#include <penumbra/imageio/compare.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/volume/volume.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace penumbra::render {
namespace {

constexpr int brick_voxels = 8;
constexpr unsigned side = 48;  // 6 bricks per axis

// One level of 8 bits: the two images differ at most by the rounding of float sums whose terms
// are the same, with the skipped samples all exactly transparent.
constexpr double tolerance = 1.0 / 255.0;

const scene::Mode all_modes[] = {
        scene::Mode::dvr,        scene::Mode::phong,     scene::Mode::half_angle, scene::Mode::sbrc,
        scene::Mode::sbrc_shell, scene::Mode::sbrc_cone, scene::Mode::reference};

// Zero everywhere but for one-voxel-thin sheets and lines on either side of brick faces (the last
// voxel of a brick and the first of the next), a lone voxel at a brick corner, and, at value 0.3,
// a small block that TFs visible only above 0.5 leave transparent.
volume::Volume thin_features() {
    std::vector<float> values(side * side * side, 0.0f);
    const auto at = [&](unsigned x, unsigned y, unsigned z) -> float& {
        return values[(std::size_t(z) * side + y) * side + x];
    };
    for (unsigned a = 4; a < side - 4; ++a) {
        for (unsigned b = 4; b < side - 4; ++b) {
            at(2 * brick_voxels, a, b) = 1.0f;      // first voxel of brick 2 in x
            at(a, b, 3 * brick_voxels - 1) = 0.8f;  // last voxel of brick 2 in z
        }
        at(a, 4 * brick_voxels, 4 * brick_voxels - 1) = 1.0f;  // a line along x on a brick edge
    }
    at(brick_voxels, brick_voxels, brick_voxels) = 1.0f;  // a corner voxel of a brick
    for (unsigned z = 34; z < 38; ++z) {
        for (unsigned y = 10; y < 14; ++y) {
            for (unsigned x = 34; x < 38; ++x) {
                at(x, y, z) = 0.3f;
            }
        }
    }
    auto volume = volume::make_volume("thin", glm::uvec3(side), glm::dvec3(1.0), values);
    EXPECT_TRUE(volume.ok());
    return std::move(volume.value());
}

// Sheets one voxel inside brick faces, where the first sample that reads them lies half a voxel
// past the face of the brick that holds them: a march that leaps a little too far misses them.
volume::Volume sheets_inside_bricks() {
    std::vector<float> values(side * side * side, 0.0f);
    const auto at = [&](unsigned x, unsigned y, unsigned z) -> float& {
        return values[(std::size_t(z) * side + y) * side + x];
    };
    for (unsigned a = 4; a < side - 4; ++a) {
        for (unsigned b = 4; b < side - 4; ++b) {
            at(2 * brick_voxels + 1, a, b) = 1.0f;
            at(a, 3 * brick_voxels - 2, b) = 0.7f;
            at(a, b, 4 * brick_voxels + 1) = 0.9f;
        }
    }
    auto volume = volume::make_volume("sheets", glm::uvec3(side), glm::dvec3(1.0), values);
    EXPECT_TRUE(volume.ok());
    return std::move(volume.value());
}

// Visible from `threshold` up, half-transparent at the top.
scene::TransferFunction step_tf(double threshold) {
    return {"step",
            {{0.0, {1.0, 0.7, 0.4}}, {1.0, {0.9, 0.9, 1.0}}},
            {{0.0, 0.0}, {threshold - 0.01, 0.0}, {threshold, 0.2}, {1.0, 0.5}}};
}

scene::FrameRequest request_for(scene::Mode mode) {
    scene::FrameRequest request;
    request.camera = scene::orbit_camera(35.0, 25.0, 2.2);
    request.light.direction = scene::direction_from_angles(-50.0, 30.0);
    request.settings.mode = mode;
    request.settings.width = 64;
    request.settings.height = 64;
    request.settings.sample_distance = 1.0 / 160.0;
    request.settings.background = {0.1, 0.2, 0.3};
    request.settings.phong = true;
    request.settings.light_buffer.slices = 48;
    request.settings.light_buffer.resolution = 48;
    request.transfer_function = step_tf(0.5);
    return request;
}

class EmptySpaceTest : public ::testing::Test {
protected:
    void SetUp() override {
        RendererOptions options;
        options.brick_voxels = brick_voxels;
        auto created = Renderer::create(options);
        ASSERT_TRUE(created.ok()) << created.error().to_string();
        renderer_ = std::move(created.value());
        volume_ = std::make_shared<const volume::Volume>(thin_features());
        ASSERT_TRUE(renderer_->set_volume(volume_).ok());
    }

    Frame render(scene::FrameRequest request, bool skipping) {
        request.settings.empty_space_skipping = skipping;
        auto frame = renderer_->render(request);
        EXPECT_TRUE(frame.ok()) << frame.error().to_string();
        return frame.ok() ? std::move(frame.value()) : Frame{};
    }

    static bool ran(const Frame& frame, const std::string& pass) {
        for (const PassTiming& timing : frame.report.passes) {
            if (timing.name == pass) {
                return true;
            }
        }
        return false;
    }

    // Renders with and without skipping and expects the same image; returns how many pixels
    // differ from the background, so that callers can check there was something to see.
    int expect_same_image(const scene::FrameRequest& request, const std::string& label) {
        const Frame skipped = render(request, true);
        const Frame marched = render(request, false);
        auto difference = imageio::compare_images(base::to_rgba_f(skipped.image),
                                                  base::to_rgba_f(marched.image));
        EXPECT_TRUE(difference.ok());
        if (difference.ok()) {
            EXPECT_LE(difference->max_error, tolerance) << label;
        }
        // The camera sees the whole box with background around it, so corner (0, 0) is background.
        int drawn = 0;
        const base::ImageRgba8& image = marched.image;
        const std::uint8_t* background = image.pixel(0, 0);
        for (int y = 0; y < image.height; ++y) {
            for (int x = 0; x < image.width; ++x) {
                drawn += std::equal(background, background + 3, image.pixel(x, y)) ? 0 : 1;
            }
        }
        return drawn;
    }

    std::unique_ptr<Renderer> renderer_;
    std::shared_ptr<const volume::Volume> volume_;
};

TEST_F(EmptySpaceTest, ThinFeaturesOnBrickFacesLookTheSameInEveryMode) {
    for (const scene::Mode mode : all_modes) {
        const std::string label = scene::to_string(mode);
        SCOPED_TRACE(label);
        EXPECT_GT(expect_same_image(request_for(mode), label), 200);
    }
}

TEST_F(EmptySpaceTest, FullyTransparentTransferFunctionGivesTheBackgroundEitherWay) {
    for (const scene::Mode mode : all_modes) {
        SCOPED_TRACE(scene::to_string(mode));
        auto request = request_for(mode);
        request.transfer_function = {"empty", {}, {}};
        EXPECT_EQ(expect_same_image(request, scene::to_string(mode)), 0);
    }
}

TEST_F(EmptySpaceTest, FullyOpaqueTransferFunctionLooksTheSame) {
    for (const scene::Mode mode : all_modes) {
        SCOPED_TRACE(scene::to_string(mode));
        auto request = request_for(mode);
        request.transfer_function = {"opaque", {{0.0, {0.9, 0.8, 0.7}}}, {{0.0, 1.0}}};
        EXPECT_GT(expect_same_image(request, scene::to_string(mode)), 1000);
    }
}

// The light buffer itself, not only the images it shades: each builder fills the same layers with
// skipping on and off, for a light along a grid axis (a walk through the bricks that never
// crosses the other axes' faces) and oblique ones, directional and point.
TEST_F(EmptySpaceTest, LightBufferLayersAreTheSameWithAndWithoutSkipping) {
    const scene::LightBufferBuilder builders[] = {scene::LightBufferBuilder::multi_slice,
                                                  scene::LightBufferBuilder::per_slice};
    const glm::dvec3 directions[] = {{1.0, 0.0, 0.0},
                                     {0.0, 0.0, -1.0},
                                     scene::direction_from_angles(-50.0, 30.0),
                                     scene::direction_from_angles(120.0, -65.0)};
    for (const auto& volume : {thin_features(), sheets_inside_bricks()}) {
        ASSERT_TRUE(renderer_->set_volume(std::make_shared<const volume::Volume>(volume)).ok());
        for (const scene::LightBufferBuilder builder : builders) {
            for (const glm::dvec3& direction : directions) {
                for (const bool point_light : {false, true}) {
                    SCOPED_TRACE(volume.name + ", " + scene::to_string(builder) +
                                 (point_light ? ", point" : ", directional") + " light from " +
                                 std::to_string(direction.x) + ", " + std::to_string(direction.y) +
                                 ", " + std::to_string(direction.z));
                    auto request = request_for(scene::Mode::sbrc);
                    request.settings.light_buffer.builder = builder;
                    request.light.direction = direction;
                    if (point_light) {
                        request.light.type = scene::LightType::point;
                        request.light.position = -1.3 * direction;
                    }
                    render(request, true);
                    auto skipped = renderer_->read_light_buffer();
                    render(request, false);
                    auto marched = renderer_->read_light_buffer();
                    ASSERT_TRUE(skipped.ok() && marched.ok());
                    ASSERT_EQ(skipped->values.size(), marched->values.size());
                    float largest = 0.0f;
                    float darkest = 1.0f;
                    for (std::size_t i = 0; i < marched->values.size(); ++i) {
                        largest = std::max(largest,
                                           std::abs(skipped->values[i] - marched->values[i]));
                        darkest = std::min(darkest, marched->values[i]);
                    }
                    // A slab of empty bricks lets all the light through either way (a factor of
                    // exactly 1); half floats hold the rest alike.
                    EXPECT_LE(largest, 1e-3f);
                    EXPECT_LT(darkest, 0.5f) << "the sheets should cast shadows";
                }
            }
        }
    }
}

// The block at 0.3 sits in bricks that a TF starting at 0.5 leaves empty; after the TF changes
// to show it, its bricks must be classified again before any ray skips them.
TEST_F(EmptySpaceTest, TransferFunctionChangeShowsBricksThatWereEmpty) {
    for (const scene::Mode mode : all_modes) {
        SCOPED_TRACE(scene::to_string(mode));
        auto request = request_for(mode);
        const Frame before = render(request, true);
        EXPECT_TRUE(ran(before, "classify_bricks"));
        request.transfer_function = step_tf(0.25);
        const Frame after = render(request, true);
        EXPECT_TRUE(ran(after, "classify_bricks"));
        const Frame marched = render(request, false);
        auto difference = imageio::compare_images(base::to_rgba_f(after.image),
                                                  base::to_rgba_f(marched.image));
        ASSERT_TRUE(difference.ok());
        EXPECT_LE(difference->max_error, tolerance);
        auto changed = imageio::compare_images(base::to_rgba_f(before.image),
                                               base::to_rgba_f(after.image));
        ASSERT_TRUE(changed.ok());
        EXPECT_GT(changed->max_error, 0.1) << "the block at 0.3 should have appeared";
    }
}

// The reference mode's shadow rays on the real Colin27 head: they leap the bricks the transfer
// function leaves transparent and look the grid up once per occupied brick, and every sample they
// leave out is exactly transparent, so the image is the same to the byte with and without skipping.
// The times of both are printed: the shadow rays are most of the reference's work.
TEST(EmptySpaceRealData, ReferenceShadowRaysGiveTheSameBytesWithAndWithoutSkipping) {
    auto loaded = volume::load_volume("/usr/share/mricron/templates/ch2.nii.gz");
    ASSERT_TRUE(loaded.ok()) << loaded.error().to_string()
                             << " (the install step gets it from Debian's mricron-data)";
    auto renderer = Renderer::create();
    ASSERT_TRUE(renderer.ok()) << renderer.error().to_string();
    ASSERT_TRUE((*renderer)->set_volume(std::make_shared<const volume::Volume>(*loaded)).ok());
    scene::FrameRequest request;
    request.camera = scene::orbit_camera(30.0, 15.0, 2.6);
    request.light.direction = scene::direction_from_angles(-60.0, 35.0);
    request.settings.mode = scene::Mode::reference;
    request.settings.width = 48;
    request.settings.height = 48;
    request.settings.sample_distance = 1.0 / 128.0;
    // Air and the faint background noise transparent, the tissue faint enough that camera rays
    // go deep and each of their samples casts a long shadow ray.
    request.transfer_function = {"faint tissue",
                                 {{0.0, {1.0, 0.8, 0.7}}, {1.0, {1.0, 1.0, 0.9}}},
                                 {{0.0, 0.0}, {0.15, 0.0}, {0.2, 0.02}, {1.0, 0.06}}};

    const auto render = [&](bool skipping) {
        request.settings.empty_space_skipping = skipping;
        // Compiles the variant and classifies the bricks, from another view so that nothing of
        // the frame timed below is kept.
        scene::FrameRequest warm_up = request;
        warm_up.camera = scene::orbit_camera(-30.0, 15.0, 2.6);
        (void)(*renderer)->render(warm_up);
        const auto start = std::chrono::steady_clock::now();
        auto frame = (*renderer)->render(request);
        const double ms =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                        .count();
        EXPECT_TRUE(frame.ok()) << frame.error().to_string();
        return std::make_pair(frame.ok() ? std::move(frame->image) : base::ImageRgba8{}, ms);
    };
    const auto [skipped, skipped_ms] = render(true);
    const auto [marched, marched_ms] = render(false);
    ASSERT_EQ(skipped.width, marched.width);
    ASSERT_EQ(skipped.height, marched.height);
    std::size_t differing = 0;
    int drawn = 0;
    for (int y = 0; y < skipped.height; ++y) {
        for (int x = 0; x < skipped.width; ++x) {
            differing +=
                    std::equal(skipped.pixel(x, y), skipped.pixel(x, y) + 4, marched.pixel(x, y))
                            ? 0
                            : 1;
            drawn += marched.pixel(x, y)[0] + marched.pixel(x, y)[1] > 0 ? 1 : 0;
        }
    }
    EXPECT_EQ(differing, 0u);
    EXPECT_GT(drawn, 48 * 48 / 4);  // the head, not an empty frame
    std::printf(
            "[ measured ] reference mode on ch2, %dx%d: %.1f ms with skipping, %.1f ms "
            "without (ratio %.2f)\n",
            request.settings.width, request.settings.height, skipped_ms, marched_ms,
            marched_ms / skipped_ms);
}

}  // namespace
}  // namespace penumbra::render
