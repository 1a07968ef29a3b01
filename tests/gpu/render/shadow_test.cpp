// The shadowing modes: the light attenuation buffer and its two builders, sbrc and its
// scattering variants, half-angle slicing and the shadow-ray reference, checked against analytic
// transmittance, against the CPU reference, and against each other.

#include "receiver_scene.hpp"
#include "synthetic_volumes.hpp"

#include <penumbra/imageio/compare.hpp>
#include <penumbra/reference/cpu_renderer.hpp>
#include <penumbra/render/renderer.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace penumbra::render {
namespace {

class ShadowTest : public ::testing::Test {
protected:
    void SetUp() override {
        auto created = Renderer::create();
        ASSERT_TRUE(created.ok()) << created.error().to_string();
        renderer_ = std::move(created.value());
    }

    void use(const volume::Volume& volume) {
        volume_ = std::make_shared<const volume::Volume>(volume);
        ASSERT_TRUE(renderer_->set_volume(volume_).ok());
    }

    Frame render(const scene::FrameRequest& request) {
        auto frame = renderer_->render(request);
        EXPECT_TRUE(frame.ok()) << frame.error().to_string();
        return frame.ok() ? std::move(frame.value()) : Frame{};
    }

    double error_against(const Frame& frame, const base::ImageRgbaF& reference) {
        auto difference = imageio::compare_images(base::to_rgba_f(frame.image), reference);
        EXPECT_TRUE(difference.ok());
        return difference.ok() ? difference->rms_error : 1.0;
    }

    std::unique_ptr<Renderer> renderer_;
    std::shared_ptr<const volume::Volume> volume_;
};

// A soft medium lit from the side, seen at an angle: shadows everywhere, no surfaces.
scene::FrameRequest radial_scene(scene::Mode mode, int size = 48) {
    scene::FrameRequest request;
    request.camera = scene::orbit_camera(20.0, 25.0, 2.4);
    request.light.direction = scene::direction_from_angles(-70.0, 30.0);
    request.light.ambient = 0.1;
    request.settings.mode = mode;
    request.settings.width = size;
    request.settings.height = size;
    request.settings.sample_distance = 1.0 / 96.0;
    request.transfer_function = {"soft",
                                 {{0.0, {1.0, 0.9, 0.8}}, {1.0, {1.0, 1.0, 1.0}}},
                                 {{0.0, 0.0}, {0.3, 0.0}, {1.0, 0.08}}};
    return request;
}

TEST_F(ShadowTest, BothLightBufferBuildersGiveTheSameLayers) {
    use(test::radial_volume(32));
    for (const auto& [point_light, slab_samples] :
         {std::pair{false, 1}, std::pair{true, 1}, std::pair{false, 3}, std::pair{true, 0}}) {
        SCOPED_TRACE(std::string(point_light ? "point light" : "directional light") +
                     ", slab samples " + std::to_string(slab_samples));
        auto request = radial_scene(scene::Mode::sbrc, 16);
        if (point_light) {
            request.light.type = scene::LightType::point;
            request.light.position = {1.2, -0.9, 1.0};
        }
        request.settings.light_buffer.slab_samples = slab_samples;
        request.settings.light_buffer.slices = 48;
        request.settings.light_buffer.resolution = 40;
        request.settings.light_buffer.builder = scene::LightBufferBuilder::per_slice;
        render(request);
        auto per_slice = renderer_->read_light_buffer();
        request.settings.light_buffer.builder = scene::LightBufferBuilder::multi_slice;
        render(request);
        auto multi_slice = renderer_->read_light_buffer();
        ASSERT_TRUE(per_slice.ok() && multi_slice.ok());
        ASSERT_EQ(per_slice->values.size(), multi_slice->values.size());
        ASSERT_EQ(per_slice->values.size(), 48u * 40u * 40u);
        double sum = 0.0;
        double largest = 0.0;
        std::size_t far_off = 0;
        double darkest = 1.0;
        for (std::size_t i = 0; i < per_slice->values.size(); ++i) {
            const double d = std::abs(per_slice->values[i] - multi_slice->values[i]);
            sum += d;
            largest = std::max(largest, d);
            far_off += d > 0.01 ? 1 : 0;
            darkest = std::min(darkest, static_cast<double>(multi_slice->values[i]));
        }
        // Both write half floats (about 3 significant digits); rasterisation may decide a
        // texel on the box silhouette differently from the compute builder's inside test.
        EXPECT_LT(sum / static_cast<double>(per_slice->values.size()), 1e-3);
        EXPECT_LT(static_cast<double>(far_off),
                  0.002 * static_cast<double>(per_slice->values.size()))
                << "largest difference " << largest;
        EXPECT_LT(darkest, 0.5);  // the medium really casts a shadow
    }
}

TEST_F(ShadowTest, FirstLayerIsUnlitAndLayersNeverBrighten) {
    use(test::radial_volume(24));
    auto request = radial_scene(scene::Mode::sbrc, 16);
    request.settings.light_buffer.slices = 20;
    request.settings.light_buffer.resolution = 24;
    render(request);
    auto buffer = renderer_->read_light_buffer();
    ASSERT_TRUE(buffer.ok());
    const std::size_t layer = 24u * 24u;
    for (std::size_t i = 0; i < layer; ++i) {
        ASSERT_FLOAT_EQ(buffer->values[i], 1.0f);
        for (std::size_t k = 1; k < 20; ++k) {
            ASSERT_LE(buffer->values[k * layer + i], buffer->values[(k - 1) * layer + i] + 1e-3f);
        }
    }
}

// Light travels along -x through a slab of known optical depth onto a receiver; half the receiver
// is behind the slab. With extinction compositing and a TF linear in the value up to the slab's
// value, the slab transmits exactly exp(-alpha / dt0 * thickness), and the ratio of shadowed to
// lit receiver pixels must equal that.
class SlabShadowTest : public ShadowTest, public ::testing::WithParamInterface<scene::Mode> {};

TEST_P(SlabShadowTest, SlabCastsAShadowOfThePredictedStrength) {
    constexpr unsigned n = 32;
    use(test::shadow_scene(n));
    const double slab_alpha = 0.03;  // the receiver scene's TF gives the slab's value this
    const scene::FrameRequest request = test::receiver_scene(GetParam());
    const Frame frame = render(request);
    const auto mean_red = [&](int row0, int row1) { return test::receiver_red(frame, row0, row1); };
    const double shadowed = mean_red(40, 47);
    const double lit = mean_red(17, 24);
    ASSERT_GT(lit, 40.0);
    const double thickness = 4.0 / n;
    const double expected =
            std::exp(-slab_alpha / request.settings.opacity_unit_distance * thickness);
    EXPECT_NEAR(shadowed / lit, expected, 0.01)
            << scene::to_string(GetParam()) << ": shadowed " << shadowed << ", lit " << lit;
}

INSTANTIATE_TEST_SUITE_P(Modes, SlabShadowTest,
                         ::testing::Values(scene::Mode::reference, scene::Mode::sbrc,
                                           scene::Mode::half_angle),
                         [](const auto& param_info) {
                             return std::string(scene::to_string(param_info.param));
                         });

// Tricubic too: the CPU sums the B-spline's 64 voxels, the GPU takes 8 linear fetches (3 x 8 for
// the gradient), so agreeing tests the fetches' weights and texel offsets.
TEST_F(ShadowTest, GpuReferenceMatchesCpuReference) {
    const volume::Volume volume = test::radial_volume(32);
    use(volume);
    for (const auto& [point_light, reconstruction] :
         {std::pair{false, scene::Reconstruction::trilinear},
          std::pair{true, scene::Reconstruction::trilinear},
          std::pair{false, scene::Reconstruction::tricubic},
          std::pair{true, scene::Reconstruction::tricubic}}) {
        SCOPED_TRACE(point_light ? "point light" : "directional light");
        SCOPED_TRACE(scene::to_string(reconstruction));
        auto request = radial_scene(scene::Mode::reference);
        request.settings.phong = true;
        request.settings.reconstruction = reconstruction;
        if (point_light) {
            request.light.type = scene::LightType::point;
            request.light.position = {1.0, -1.1, 0.9};
        }
        const Frame frame = render(request);
        auto expected = reference::render_cpu(volume, request);
        ASSERT_TRUE(expected.ok()) << expected.error().to_string();
        auto difference = imageio::compare_images(base::to_rgba_f(frame.image), *expected);
        ASSERT_TRUE(difference.ok());
        EXPECT_LE(difference->max_error, 3.0 / 255.0);
        EXPECT_LE(difference->mean_error, 0.6 / 255.0);
    }
}

TEST_F(ShadowTest, SbrcConvergesTowardTheReferenceAsSlicesAndResolutionGrow) {
    use(test::radial_volume(32));
    const Frame reference_frame = render(radial_scene(scene::Mode::reference));
    const base::ImageRgbaF reference = base::to_rgba_f(reference_frame.image);
    const Frame unshadowed = render(radial_scene(scene::Mode::dvr));
    for (const auto lookup : {scene::LightLookup::interpolate, scene::LightLookup::local}) {
        SCOPED_TRACE(scene::to_string(lookup));
        std::vector<double> errors;
        for (const auto& [slices, resolution] :
             {std::pair{4, 8}, std::pair{16, 24}, std::pair{96, 96}}) {
            auto request = radial_scene(scene::Mode::sbrc);
            request.settings.light_buffer.slices = slices;
            request.settings.light_buffer.resolution = resolution;
            request.settings.light_buffer.lookup = lookup;
            errors.push_back(error_against(render(request), reference));
        }
        EXPECT_LT(errors[1], errors[0]);
        EXPECT_LT(errors[2], 0.7 * errors[1]);
        EXPECT_LT(errors[2], 0.02);
        // Shadows matter here: ignoring them is far worse than a fine light buffer.
        EXPECT_GT(error_against(unshadowed, reference), 3.0 * errors[2]);
    }
}

// An opaque ball lit from the side with few, deep slices: the lit side shadows itself within the
// first slab. Interpolating between layers spreads that over the slab, so the shading depends on
// where the surface sits between two slice planes; the local lookup puts it at the surface and
// follows the reference far more closely. Sub-sampling the slabs helps the paper's lookup too.
TEST_F(ShadowTest, LocalLookupFollowsTheReferenceOnAnOpaqueSurface) {
    use(test::sphere_volume(48, 0.4f));
    scene::FrameRequest request;
    request.camera = scene::orbit_camera(30.0, 20.0, 2.2);
    request.light.direction = scene::direction_from_angles(-60.0, 35.0);
    request.light.ambient = 0.1;
    request.settings.width = 64;
    request.settings.height = 64;
    request.settings.sample_distance = 1.0 / 256.0;
    request.transfer_function = {
            "ball", {{0.0, {1.0, 1.0, 1.0}}}, {{0.0, 0.0}, {0.4, 0.0}, {0.6, 0.5}, {1.0, 0.5}}};
    request.settings.mode = scene::Mode::reference;
    const base::ImageRgbaF reference = base::to_rgba_f(render(request).image);

    request.settings.mode = scene::Mode::sbrc;
    request.settings.light_buffer.slices = 24;
    request.settings.light_buffer.resolution = 64;
    const auto error_with = [&](scene::LightLookup lookup, int slab_samples) {
        request.settings.light_buffer.lookup = lookup;
        request.settings.light_buffer.slab_samples = slab_samples;
        return error_against(render(request), reference);
    };
    const double paper = error_with(scene::LightLookup::interpolate, 1);
    const double paper_sampled = error_with(scene::LightLookup::interpolate, 0);
    const double local = error_with(scene::LightLookup::local, 0);
    EXPECT_LT(local, 0.5 * paper) << "interpolate " << paper << ", local " << local;
    EXPECT_LT(paper_sampled, paper) << "slab sampling should help the interpolating lookup too";
    EXPECT_LT(local, 0.04);
}

TEST_F(ShadowTest, ScatteringModesStayCloseToSbrcAndSoftenIt) {
    use(test::radial_volume(32));
    auto request = radial_scene(scene::Mode::sbrc);
    request.settings.light_buffer.slices = 64;
    request.settings.light_buffer.resolution = 64;
    const Frame hard = render(request);
    for (const scene::Mode mode : {scene::Mode::sbrc_shell, scene::Mode::sbrc_cone}) {
        request.settings.mode = mode;
        const Frame soft = render(request);
        EXPECT_EQ(soft.report.light_buffer, render::LightBufferState::reused)
                << scene::to_string(mode);
        const double difference = error_against(soft, base::to_rgba_f(hard.image));
        EXPECT_GT(difference, 0.0) << scene::to_string(mode);
        EXPECT_LT(difference, 0.05) << scene::to_string(mode);
    }
}

TEST_F(ShadowTest, CameraMovesNeverRebuildTheLightBuffer) {
    use(test::radial_volume(24));
    auto request = radial_scene(scene::Mode::sbrc_cone, 16);
    render(request);
    const std::uint64_t builds = renderer_->light_buffer_builds();
    for (int i = 0; i < 5; ++i) {
        request.camera = scene::orbit_camera(20.0 + 30.0 * i, 10.0 * i, 2.0 + 0.1 * i);
        request.settings.mode = i % 2 == 0 ? scene::Mode::sbrc : scene::Mode::sbrc_shell;
        request.settings.width = 16 + i;  // image size is a camera matter too
        // How samples read the buffer is not what the buffer holds.
        request.settings.light_buffer.lookup =
                i % 3 == 0 ? scene::LightLookup::interpolate : scene::LightLookup::local;
        EXPECT_EQ(render(request).report.light_buffer, render::LightBufferState::reused);
    }
    EXPECT_EQ(renderer_->light_buffer_builds(), builds);
    // Anything the buffer depends on does rebuild it.
    request.light.direction = scene::direction_from_angles(10.0, 10.0);
    EXPECT_EQ(render(request).report.light_buffer, render::LightBufferState::built);
    request.settings.light_buffer.slices = 33;
    EXPECT_EQ(render(request).report.light_buffer, render::LightBufferState::built);
    request.transfer_function.opacities.back().alpha = 0.2;
    EXPECT_EQ(render(request).report.light_buffer, render::LightBufferState::built);
    request.settings.light_buffer.slab_samples = 5;
    EXPECT_EQ(render(request).report.light_buffer, render::LightBufferState::built);
    EXPECT_EQ(renderer_->light_buffer_builds(), builds + 4);
    // Modes without light-buffer shadows do not touch it.
    request.settings.mode = scene::Mode::phong;
    EXPECT_EQ(render(request).report.light_buffer, render::LightBufferState::none);
    EXPECT_EQ(renderer_->light_buffer_builds(), builds + 4);
}

TEST_F(ShadowTest, LightBuffersOfSeveralLightsStayCachedForSessionsThatShareTheRenderer) {
    use(test::radial_volume(24));
    auto first = radial_scene(scene::Mode::sbrc, 16);
    auto second = first;
    second.light.direction = scene::direction_from_angles(120.0, -10.0);
    EXPECT_EQ(render(first).report.light_buffer, render::LightBufferState::built);
    EXPECT_EQ(render(second).report.light_buffer, render::LightBufferState::built);
    const std::uint64_t builds = renderer_->light_buffer_builds();
    for (int i = 0; i < 3; ++i) {
        const Frame a = render(first);
        const Frame b = render(second);
        EXPECT_EQ(a.report.light_buffer, render::LightBufferState::reused);
        EXPECT_EQ(b.report.light_buffer, render::LightBufferState::reused);
        EXPECT_NE(a.image.pixels, b.image.pixels);  // each used its own light's buffer
    }
    EXPECT_EQ(renderer_->light_buffer_builds(), builds);
}

TEST_F(ShadowTest, HalfAngleHandlesLightEqualAndOppositeToTheView) {
    use(test::radial_volume(32));
    for (const double sign : {1.0, -1.0}) {
        SCOPED_TRACE(sign > 0 ? "light behind the viewer" : "light facing the viewer");
        auto request = radial_scene(scene::Mode::half_angle);
        request.settings.light_buffer.slices = 64;
        request.settings.light_buffer.resolution = 48;
        // direction points toward the light: +eye puts the light behind the camera.
        request.light.direction = sign * glm::normalize(request.camera.eye - request.camera.target);
        const Frame half_angle = render(request);
        request.settings.mode = scene::Mode::reference;
        const Frame reference = render(request);
        int lit = 0;
        for (int y = 0; y < 48; ++y) {
            for (int x = 0; x < 48; ++x) {
                lit += half_angle.image.pixel(x, y)[0] > 20 ? 1 : 0;
            }
        }
        EXPECT_GT(lit, 48 * 48 / 10);
        EXPECT_LT(error_against(half_angle, base::to_rgba_f(reference.image)), 0.05);
    }
}

TEST_F(ShadowTest, OneSliceAndTheLayerLimitBothWork) {
    use(test::radial_volume(16));
    for (const auto builder :
         {scene::LightBufferBuilder::per_slice, scene::LightBufferBuilder::multi_slice}) {
        for (const int slices : {1, renderer_->info().max_array_texture_layers}) {
            SCOPED_TRACE(std::string(scene::to_string(builder)) + " " + std::to_string(slices));
            auto request = radial_scene(scene::Mode::sbrc, 12);
            request.settings.light_buffer.slices = slices;
            request.settings.light_buffer.resolution = 8;
            request.settings.light_buffer.builder = builder;
            const Frame frame = render(request);
            EXPECT_EQ(frame.report.light_buffer, render::LightBufferState::built);
            auto buffer = renderer_->read_light_buffer();
            ASSERT_TRUE(buffer.ok());
            EXPECT_EQ(buffer->slices, slices);
            for (const float v : buffer->values) {
                ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f) << v;
            }
        }
    }
}

TEST_F(ShadowTest, CompensationBrightensShadowsButNeverAboveUnlit) {
    use(test::radial_volume(24));
    auto request = radial_scene(scene::Mode::sbrc, 24);
    request.settings.light_buffer.slices = 64;
    request.settings.light_buffer.resolution = 32;
    std::vector<double> mean_transmittance;
    for (const double compensation : {0.0, 1.0, 4.0, 1000.0}) {
        request.settings.light_buffer.compensation = compensation;
        render(request);
        auto buffer = renderer_->read_light_buffer();
        ASSERT_TRUE(buffer.ok());
        double sum = 0.0;
        for (const float v : buffer->values) {
            ASSERT_TRUE(std::isfinite(v) && v <= 1.0f) << "compensation " << compensation;
            sum += v;
        }
        mean_transmittance.push_back(sum / static_cast<double>(buffer->values.size()));
    }
    EXPECT_LT(mean_transmittance[0], mean_transmittance[1]);
    EXPECT_LT(mean_transmittance[1], mean_transmittance[2]);
    EXPECT_LE(mean_transmittance[3], 1.0);
}

TEST_F(ShadowTest, InsetShowsTheLastLayer) {
    use(test::radial_volume(24));
    auto request = radial_scene(scene::Mode::sbrc, 16);
    request.settings.light_buffer.resolution = 20;
    render(request);
    auto inset = renderer_->light_inset();
    ASSERT_TRUE(inset.ok());
    EXPECT_EQ(inset->width, 20);
    // The medium's shadow is darkest in the middle of the last layer, unlit corners stay white.
    EXPECT_LT(inset->pixel(10, 10)[0], inset->pixel(0, 0)[0]);
    request.settings.mode = scene::Mode::dvr;
    render(request);
    auto none = renderer_->light_inset();
    EXPECT_TRUE(none.ok());  // still the last light buffer; dvr did not replace it
}

}  // namespace
}  // namespace penumbra::render
