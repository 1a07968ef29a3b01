// The converged truth of `bench accuracy` against a closed form, and its cache on disk.
//
// A slab of constant extinction sigma and thickness d, white, lit by a directional light from the
// camera's side, seen head-on through black: along a ray at angle theta to the slab's normal
// (c = cos theta) the emission-absorption integral is
//   C = ambient (1 - exp(-sigma d / c)) + diffuse / (1 + c) (1 - exp(-sigma d (1 + c) / c)),
// the first term the unshadowed ambient light, the second the light that a shadow ray of length
// t c finds at camera depth t. A coarse unjittered step misplaces the slab's faces by up to half
// a step; the truth (jittered, averaged over frames) must converge to C all the same.

#include <penumbra/bench/truth.hpp>
#include <penumbra/render/renderer.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <vector>

namespace penumbra::bench {
namespace {

constexpr unsigned depth_voxels = 64;
constexpr unsigned slab_begin = 20;  // voxels along z
constexpr unsigned slab_end = 43;    // 23 voxels
constexpr double sigma_d = 0.5;      // the slab's optical thickness head-on
constexpr int side = 64;

// 8 x 8 x 64 voxels stretched to a cube: value 1 in the slab, 0 elsewhere. Between the last voxel
// of one and the first of the other the value falls linearly, so with an opacity linear in the
// value and extinction compositing the slab's optical thickness is that of sharp faces midway.
volume::Volume slab() {
    const glm::uvec3 dims(8, 8, depth_voxels);
    std::vector<float> values(std::size_t{dims.x} * dims.y * dims.z, 0.0f);
    for (unsigned z = slab_begin; z < slab_end; ++z) {
        std::fill_n(values.begin() + std::ptrdiff_t{z} * dims.x * dims.y, dims.x * dims.y, 1.0f);
    }
    return volume::make_volume("slab", dims, glm::dvec3(8.0, 8.0, 1.0), values).value();
}

// Head-on from +z through a narrow field, lit from the camera's side, unshaded by gradients.
scene::FrameRequest view() {
    scene::FrameRequest request;
    request.camera = {{0.0, 0.0, 8.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, 6.0};
    request.light.type = scene::LightType::directional;
    request.light.direction = {0.0, 0.0, 1.0};
    const double thickness = static_cast<double>(slab_end - slab_begin) / depth_voxels;
    const double unit = 0.1;
    // Extinction compositing: sample opacity 1 - exp(-alpha / unit * step), so sigma = alpha /
    // unit.
    request.transfer_function = {"slab",
                                 {{0.0, {1.0, 1.0, 1.0}}, {1.0, {1.0, 1.0, 1.0}}},
                                 {{0.0, 0.0}, {1.0, sigma_d / thickness * unit}}};
    scene::RenderSettings& s = request.settings;
    s.width = side;
    s.height = side;
    s.compositing = scene::Compositing::extinction;
    s.opacity_unit_distance = unit;
    s.background = glm::dvec3(0.0);
    s.phong = false;
    return request;
}

// The closed form at pixel (x, y), or a negative value where the pixel's ray leaves the slab
// through a side.
double closed_form(const scene::FrameRequest& request, int x, int y) {
    const scene::CameraFrame frame = scene::camera_frame(request.camera, 1.0);
    const double ndc_x = (x + 0.5) / side * 2.0 - 1.0;
    const double ndc_y = 1.0 - (y + 0.5) / side * 2.0;
    const glm::dvec3 ray = glm::normalize(frame.forward + ndc_x * frame.right + ndc_y * frame.up);
    const double far_face = -0.5 + static_cast<double>(slab_begin) / depth_voxels;
    const glm::dvec3 exit = frame.eye + ray * ((far_face - frame.eye.z) / ray.z);
    if (std::abs(exit.x) > 0.45 || std::abs(exit.y) > 0.45) {
        return -1.0;
    }
    const double c = std::abs(ray.z);
    const double ambient = request.light.ambient;
    const double diffuse = request.settings.shading.diffuse;
    return ambient * (1.0 - std::exp(-sigma_d / c)) +
           diffuse / (1.0 + c) * (1.0 - std::exp(-sigma_d * (1.0 + c) / c));
}

struct Error {
    double mean = 0.0;
    double max = 0.0;
    int pixels = 0;
};

// The image's red channel against the closed form, over the pixels that see both faces.
Error error_of(const scene::FrameRequest& request, const base::ImageRgba8& image) {
    Error error;
    for (int y = 0; y < side; ++y) {
        for (int x = 0; x < side; ++x) {
            const double expected = closed_form(request, x, y);
            if (expected < 0.0) {
                continue;
            }
            const double got = image.pixels[(std::size_t(y) * side + x) * 4] / 255.0;
            error.mean += std::abs(got - expected);
            error.max = std::max(error.max, std::abs(got - expected));
            ++error.pixels;
        }
    }
    error.mean /= std::max(1, error.pixels);
    return error;
}

class TruthTest : public ::testing::Test {
protected:
    void SetUp() override {
        auto created = render::Renderer::create();
        ASSERT_TRUE(created.ok()) << created.error().to_string();
        renderer_ = std::move(created.value());
        ASSERT_TRUE(renderer_->set_volume(volume_).ok());
    }

    std::unique_ptr<render::Renderer> renderer_;
    std::shared_ptr<const volume::Volume> volume_ = std::make_shared<const volume::Volume>(slab());
};

TEST_F(TruthTest, ConvergesToTheClosedFormOfASlabWhereAFixedStepDoesNot) {
    const scene::FrameRequest request = view();
    quality::AccuracyBench bench(*renderer_, 1);
    // The slab is 4.5 of these steps thick: a fixed step puts 4 or 5 samples in it, never 4.5.
    const double coarse = (slab_end - slab_begin) / 4.5 / depth_voxels;
    scene::FrameRequest fixed = truth_request(request, {coarse, 2});
    fixed.settings.jitter = false;
    auto fixed_image = renderer_->render(fixed);
    ASSERT_TRUE(fixed_image.ok()) << fixed_image.error().to_string();
    const Error fixed_error = error_of(request, fixed_image->image);
    ASSERT_GT(fixed_error.pixels, side * side / 4);

    auto coarse_truth = render_truth(bench, request, {coarse, 16});
    ASSERT_TRUE(coarse_truth.ok()) << coarse_truth.error().to_string();
    const Error coarse_error = error_of(request, *coarse_truth);
    auto fine_truth = render_truth(bench, request, {1.0 / 128.0, 8});
    ASSERT_TRUE(fine_truth.ok()) << fine_truth.error().to_string();
    const Error fine_error = error_of(request, *fine_truth);

    EXPECT_GT(fixed_error.mean, 0.02) << "the fixed step should miss the closed form";
    EXPECT_LT(coarse_error.mean, fixed_error.mean / 4.0);
    EXPECT_LT(fine_error.mean, 1.0 / 255.0);
    EXPECT_LT(fine_error.max, 3.0 / 255.0);
    std::printf(
            "mean |error| (max): fixed step %.4f (%.4f), jittered 16 frames %.4f (%.4f), "
            "1/128 8 frames %.4f (%.4f) over %d pixels\n",
            fixed_error.mean, fixed_error.max, coarse_error.mean, coarse_error.max, fine_error.mean,
            fine_error.max, fine_error.pixels);
}

TEST_F(TruthTest, OneFrameIsNoTruth) {
    quality::AccuracyBench bench(*renderer_, 1);
    auto truth = render_truth(bench, view(), {1.0 / 64.0, 1});
    ASSERT_FALSE(truth.ok());
    EXPECT_EQ(truth.error().code, base::ErrorCode::invalid_argument);
}

TEST_F(TruthTest, TheCacheKeepsATruthOnDiskAndRendersItOnce) {
    const std::filesystem::path folder =
            std::filesystem::path(::testing::TempDir()) / "penumbra_truth_cache_test";
    std::filesystem::remove_all(folder);
    const quality::TruthMethod method{1.0 / 32.0, 2};
    scene::FrameRequest request = view();
    request.settings.width = request.settings.height = 16;
    quality::AccuracyBench bench(*renderer_, 1);

    TruthCache first(folder);
    auto rendered = first.truth(bench, *volume_, request, method);
    ASSERT_TRUE(rendered.ok()) << rendered.error().to_string();
    EXPECT_EQ(rendered->source, TruthCache::Source::rendered);
    ASSERT_TRUE(rendered->file.has_value()) << rendered->not_kept->to_string();
    const std::uint64_t frames = bench.frames();
    auto again = first.truth(bench, *volume_, request, method);
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(again->source, TruthCache::Source::memory);

    TruthCache second(folder);  // a later run
    auto read = second.truth(bench, *volume_, request, method);
    ASSERT_TRUE(read.ok()) << read.error().to_string();
    EXPECT_EQ(read->source, TruthCache::Source::disk);
    EXPECT_EQ(read->image.pixels, rendered->image.pixels);
    EXPECT_EQ(bench.frames(), frames) << "a kept truth was rendered again";

    // A key file that names another case (a digest's collision) is not believed.
    std::filesystem::path key = *rendered->file;
    key.replace_extension(".key");
    std::ofstream(key) << "another case\n";
    TruthCache third(folder);
    auto collided = third.truth(bench, *volume_, request, method);
    ASSERT_TRUE(collided.ok());
    EXPECT_EQ(collided->source, TruthCache::Source::rendered);
    std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace penumbra::bench
