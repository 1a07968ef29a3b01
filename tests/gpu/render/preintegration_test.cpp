// Pre-integrated classification: the table shaders/preintegration_table.comp builds against a
// numerical integration in double; images of a steep transfer function closer to a fine-step
// reference than per-sample classification; front == back exactly the per-sample image; the GPU
// against the CPU reference; and empty-space skipping keeping the segments that cross into or
// out of an empty brick.

#include "preintegration_table.hpp"
#include "program_cache.hpp"
#include "synthetic_volumes.hpp"
#include "transfer_function_texture.hpp"

#include <penumbra/gpu/commands.hpp>
#include <penumbra/gpu/context.hpp>
#include <penumbra/gpu/shader_library.hpp>
#include <penumbra/imageio/compare.hpp>
#include <penumbra/optics/preintegration.hpp>
#include <penumbra/reference/cpu_renderer.hpp>
#include <penumbra/reference/volume_sampler.hpp>
#include <penumbra/render/renderer.hpp>

#include <glm/common.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

namespace penumbra::render {
namespace {

const scene::ValueDomain normalised{0.0, 1.0, false};

// A thin opaque range: opacity 1 over [0.495, 0.505] only.
scene::TransferFunction spike_tf() {
    return {"spike",
            {{0.0, {0.2, 0.4, 1.0}}, {0.5, {1.0, 0.9, 0.6}}, {1.0, {1.0, 0.2, 0.1}}},
            {{0.0, 0.0}, {0.49, 0.0}, {0.495, 1.0}, {0.505, 1.0}, {0.51, 0.0}, {1.0, 0.0}}};
}

std::vector<scene::TransferFunction> table_cases() {
    return {
            {"ramps",
             {{0.0, {0.0, 0.5, 1.0}}, {1.0, {1.0, 0.5, 0.0}}},
             {{0.0, 0.0}, {0.3, 0.2}, {0.7, 0.05}, {1.0, 0.6}}},
            {"step", {{0.0, {0.9, 0.8, 0.7}}}, {{0.0, 0.0}, {0.6, 0.0}, {0.601, 1.0}, {1.0, 1.0}}},
            spike_tf(),
            {"opaque ends",
             {{0.0, {1.0, 0.0, 0.0}}, {1.0, {0.0, 0.0, 1.0}}},
             {{0.0, 1.0}, {0.2, 0.3}, {0.8, 0.3}, {1.0, 1.0}}},
            {"transparent ends",
             {{0.0, {0.3, 1.0, 0.3}}},
             {{0.0, 0.0}, {0.1, 0.0}, {0.5, 0.7}, {0.9, 0.0}, {1.0, 0.0}}},
    };
}

// The integral from 0 of (depth * colour, depth) over the TF as the GPU filters it, by the
// trapezoidal rule in double on a grid 64 times finer than the TF's entries.
class FineIntegral {
public:
    FineIntegral(const reference::TransferFunctionTable& tf, bool extinction)
        : tf_(tf)
        , extinction_(extinction) {
        sums_.resize(points + 1);
        glm::dvec4 previous = at(0.0);
        for (int m = 1; m <= points; ++m) {
            const glm::dvec4 current = at(double(m) / points);
            sums_[m] = sums_[m - 1] + 0.5 * (previous + current) / double(points);
            previous = current;
        }
    }

    [[nodiscard]] glm::dvec4 operator()(double value) const {
        const double x = value * points;
        const int m = std::min(static_cast<int>(x), points - 1);
        return glm::mix(sums_[m], sums_[m + 1], x - m);
    }

    [[nodiscard]] glm::dvec4 at(double value) const {
        const glm::dvec4 c = tf_.classify(value);
        const double depth = optics::optical_depth_of_opacity(c.a, extinction_);
        return {depth * glm::dvec3(c), depth};
    }

private:
    static constexpr int points = scene::default_table_size * 64;
    const reference::TransferFunctionTable& tf_;
    bool extinction_;
    std::vector<glm::dvec4> sums_;
};

TEST(PreintegrationTable, MatchesNumericalIntegrationInDouble) {
    auto context = gpu::Context::create();
    ASSERT_TRUE(context.ok()) << context.error().to_string();
    const gpu::ShaderLibrary shaders(gpu::default_shader_dir());
    ProgramCache programs(shaders);
    TransferFunctionTexture tf_texture;
    PreintegrationTable table(false);
    const int side = table.side();
    std::vector<float> entries(std::size_t(side) * side * 4);
    for (const scene::TransferFunction& tf : table_cases()) {
        const reference::TransferFunctionTable cpu_table(tf, normalised);
        tf_texture.update(scene::bake(tf, scene::default_table_size, normalised));
        gpu::bind_texture(1, tf_texture.texture());
        for (const bool extinction : {false, true}) {
            SCOPED_TRACE(tf.name + (extinction ? ", extinction" : ", alpha"));
            auto built = table.update(programs, tf_texture.version(), extinction);
            ASSERT_TRUE(built.ok()) << built.error().to_string();
            EXPECT_TRUE(built->has_value());
            auto again = table.update(programs, tf_texture.version(), extinction);
            ASSERT_TRUE(again.ok());
            EXPECT_FALSE(again->has_value()) << "built again for the same TF and compositing";
            gpu::read_texture(table.texture(), GL_RGBA, GL_FLOAT,
                              std::as_writable_bytes(std::span(entries)));
            const FineIntegral integral(cpu_table, extinction);
            double worst_depth = 0.0;  // in transmittance
            double worst_colour = 0.0;
            for (int j = 0; j < side; j += 3) {
                for (int i = 0; i < side; i += 3) {
                    const double front = double(i) / (side - 1);
                    const double back = double(j) / (side - 1);
                    glm::dvec4 expected = integral.at(0.5 * (front + back));
                    if (i != j) {
                        const glm::dvec4 sum = integral(back) - integral(front);
                        expected = {sum.a != 0.0 ? glm::dvec3(sum) / sum.a : glm::dvec3(0.0),
                                    sum.a / (back - front)};
                    }
                    const float* got = &entries[(std::size_t(j) * side + i) * 4];
                    // What a segment one opacity unit distance long lets through: where the depth
                    // is large (an opaque entry's is 16.6) its error cannot show.
                    worst_depth = std::max(worst_depth, std::abs(std::exp(-double(got[3])) -
                                                                 std::exp(-expected.a)));
                    // The colour only matters in proportion to what the segment absorbs.
                    if (i != j && expected.a > 1e-3) {
                        for (int c = 0; c < 3; ++c) {
                            worst_colour =
                                    std::max(worst_colour, std::abs(got[c] - expected[c]) *
                                                                   std::min(1.0, expected.a));
                        }
                    }
                }
            }
            // Simpson's rule on -ln(1 - a) where a nears 1 (alpha compositing's spike and step)
            // is what keeps this above a float's rounding.
            EXPECT_LT(worst_depth, 5e-3);
            EXPECT_LT(worst_colour, 2e-3);
        }
    }
}

class PreintegrationTest : public ::testing::Test {
protected:
    void SetUp() override {
        auto created = Renderer::create(options());
        ASSERT_TRUE(created.ok()) << created.error().to_string();
        renderer_ = std::move(created.value());
    }

    virtual RendererOptions options() { return {}; }

    void use(const volume::Volume& volume) {
        volume_ = std::make_shared<const volume::Volume>(volume);
        ASSERT_TRUE(renderer_->set_volume(volume_).ok());
    }

    base::ImageRgbaF render(const scene::FrameRequest& request) {
        auto frame = renderer_->render(request);
        EXPECT_TRUE(frame.ok()) << frame.error().to_string();
        return frame.ok() ? base::to_rgba_f(frame->image) : base::ImageRgbaF(1, 1);
    }

    static imageio::ImageDifference compare(const base::ImageRgbaF& a, const base::ImageRgbaF& b) {
        auto difference = imageio::compare_images(a, b);
        EXPECT_TRUE(difference.ok());
        return difference.ok() ? *difference : imageio::ImageDifference{};
    }

    std::unique_ptr<Renderer> renderer_;
    std::shared_ptr<const volume::Volume> volume_;
};

scene::FrameRequest steep_scene(scene::Mode mode) {
    scene::FrameRequest request;
    request.camera = scene::orbit_camera(25.0, 20.0, 2.2);
    request.light.direction = scene::direction_from_angles(-60.0, 35.0);
    request.light.ambient = 0.3;
    request.settings.mode = mode;
    request.settings.width = 96;
    request.settings.height = 96;
    request.settings.background = {0.1, 0.1, 0.1};
    request.settings.sample_distance = 1.0 / 48.0;
    request.transfer_function = spike_tf();
    return request;
}

// A spherical shell of values 0.495..0.505 in a radial volume: the step of 1/48 changes the value
// by about 0.04, four times the shell's width, so per-sample classification shows it in rings.
TEST_F(PreintegrationTest, SteepTransferFunctionFollowsAFineStepReferenceBetter) {
    use(test::radial_volume(48));
    for (const scene::Mode mode : {scene::Mode::dvr, scene::Mode::phong}) {
        SCOPED_TRACE(scene::to_string(mode));
        auto fine = steep_scene(mode);
        fine.settings.sample_distance = 1.0 / 1024.0;
        const base::ImageRgbaF reference = render(fine);
        auto coarse = steep_scene(mode);
        const double per_sample = compare(render(coarse), reference).psnr;
        coarse.settings.preintegration = true;
        const double preintegrated = compare(render(coarse), reference).psnr;
        EXPECT_GT(preintegrated, per_sample + 6.0)
                << "per sample " << per_sample << " dB, pre-integrated " << preintegrated << " dB";
    }
}

// The light slabs are pre-integrated too (light_slab.glsl), in both builders. With one point per
// slab, about 0.06 of value apart along the light, the shell of values 0.495..0.505 lies between
// two points in most slabs: per-point classification lets the light through there, in rings of
// the slab spacing. The segments between the points count it: against a buffer of 16 points per
// slab (0.004 of value apart), the pre-integrated buffer of one point per slab is much closer
// (RMS transmittance 0.008 against 0.185 here, in both builders).
TEST_F(PreintegrationTest, LightSlabsCountAThinShellBetweenTheirPoints) {
    use(test::radial_volume(48));
    for (const auto builder :
         {scene::LightBufferBuilder::multi_slice, scene::LightBufferBuilder::per_slice}) {
        SCOPED_TRACE(scene::to_string(builder));
        const auto buffer = [&](int slab_samples, bool preintegration) {
            auto request = steep_scene(scene::Mode::sbrc);
            request.settings.light_buffer.slices = 48;
            request.settings.light_buffer.resolution = 64;
            request.settings.light_buffer.builder = builder;
            request.settings.light_buffer.slab_samples = slab_samples;
            request.settings.preintegration = preintegration;
            render(request);
            auto contents = renderer_->read_light_buffer();
            EXPECT_TRUE(contents.ok()) << contents.error().to_string();
            return contents.ok() ? contents->values : std::vector<float>{};
        };
        const std::vector<float> fine = buffer(scene::kMaxSlabSamples, false);
        const auto rms_from_fine = [&fine](const std::vector<float>& values) {
            EXPECT_EQ(values.size(), fine.size());
            double sum = 0.0;
            for (std::size_t i = 0; i < std::min(values.size(), fine.size()); ++i) {
                sum += (values[i] - fine[i]) * (values[i] - fine[i]);
            }
            return std::sqrt(sum / static_cast<double>(std::max<std::size_t>(1, fine.size())));
        };
        const double per_point = rms_from_fine(buffer(1, false));
        const double preintegrated = rms_from_fine(buffer(1, true));
        EXPECT_LT(preintegrated, 0.2 * per_point)
                << "RMS transmittance from 16 points per slab: per point " << per_point
                << ", pre-integrated " << preintegrated;
    }
}

// The darkening compensation (1 + a)^c works on a slab's opacity whatever classified it: on a
// constant volume, where each segment's ends agree, the pre-integrated light buffer is the
// per-point one to the bit, with compensation and without, in both compositing modes.
TEST_F(PreintegrationTest, LightSlabsWithEqualEndsAreThePerPointSlabsUnderCompensation) {
    use(test::constant_volume(glm::uvec3(24), 0.5f));
    for (const double compensation : {0.0, 0.5}) {
        for (const auto compositing : {scene::Compositing::alpha, scene::Compositing::extinction}) {
            SCOPED_TRACE("compensation " + std::to_string(compensation) + ", " +
                         scene::to_string(compositing));
            const auto buffer = [&](bool preintegration) {
                auto request = steep_scene(scene::Mode::sbrc);
                request.settings.compositing = compositing;
                request.settings.light_buffer.slices = 32;
                request.settings.light_buffer.resolution = 32;
                request.settings.light_buffer.slab_samples = 2;
                request.settings.light_buffer.compensation = compensation;
                request.settings.preintegration = preintegration;
                request.transfer_function = {
                        "visible", {{0.0, {0.9, 0.6, 0.3}}}, {{0.0, 0.05}, {1.0, 0.5}}};
                render(request);
                auto contents = renderer_->read_light_buffer();
                EXPECT_TRUE(contents.ok()) << contents.error().to_string();
                return contents.ok() ? contents->values : std::vector<float>{};
            };
            const std::vector<float> per_point = buffer(false);
            const std::vector<float> preintegrated = buffer(true);
            ASSERT_FALSE(per_point.empty());
            EXPECT_EQ(preintegrated, per_point);
            EXPECT_LT(*std::min_element(per_point.begin(), per_point.end()), 0.9f)
                    << "the volume dims the light";
        }
    }
}

// Where every segment has the same value at both ends, pre-integration is per-sample
// classification to the bit. Shaded by a directional light without shadows (phong: on a constant
// volume no gradient, the same light everywhere) the image is the same to the bit too; shadowed,
// it is not, since a segment is lit at its middle, half a step before its sample.
TEST_F(PreintegrationTest, FrontEqualToBackGivesThePerSampleImageExactly) {
    use(test::constant_volume(glm::uvec3(24), 0.5f));
    for (const scene::Mode mode : {scene::Mode::dvr, scene::Mode::phong}) {
        for (const auto compositing : {scene::Compositing::alpha, scene::Compositing::extinction}) {
            SCOPED_TRACE(std::string(scene::to_string(mode)) + ", " +
                         scene::to_string(compositing));
            auto request = steep_scene(mode);
            request.settings.compositing = compositing;
            request.transfer_function = {
                    "visible", {{0.0, {0.9, 0.6, 0.3}}}, {{0.0, 0.05}, {1.0, 0.5}}};
            const base::ImageRgbaF per_sample = render(request);
            request.settings.preintegration = true;
            const imageio::ImageDifference difference = compare(render(request), per_sample);
            EXPECT_EQ(difference.max_error, 0.0);
        }
    }
}

// The CPU integrates exactly where the GPU filters its table: on a TF whose ramps span many of
// the table's cells they agree as closely as without pre-integration. (On the spike, whose ramps
// are two or three cells wide, a ray that grazes the shell, many segments within the ramps, can
// differ by a few percent.)
TEST_F(PreintegrationTest, GpuMatchesCpuReference) {
    use(test::radial_volume(32));
    for (const scene::Mode mode : {scene::Mode::dvr, scene::Mode::reference}) {
        for (const auto compositing : {scene::Compositing::alpha, scene::Compositing::extinction}) {
            SCOPED_TRACE(std::string(scene::to_string(mode)) + ", " +
                         scene::to_string(compositing));
            auto request = steep_scene(mode);
            request.settings.width = 48;
            request.settings.height = 48;
            request.settings.compositing = compositing;
            request.settings.preintegration = true;
            request.transfer_function = {"bone-like",
                                         {{0.0, {0.9, 0.5, 0.3}}, {1.0, {1.0, 1.0, 0.9}}},
                                         {{0.0, 0.0}, {0.45, 0.0}, {0.5, 0.9}, {1.0, 0.9}}};
            auto expected = reference::render_cpu(*volume_, request);
            ASSERT_TRUE(expected.ok()) << expected.error().to_string();
            const imageio::ImageDifference difference = compare(render(request), *expected);
            EXPECT_LE(difference.max_error, 3.0 / 255.0);
            EXPECT_LE(difference.mean_error, 0.6 / 255.0);
        }
    }
}

// Bricks of 8 voxels; sheets of value 1 in a volume of 0, on either side of brick faces. The TF
// shows only values between 0.4 and 0.6, which no voxel holds: the bricks of zeros are empty, and
// what shows is the segments that cross from a zero to a sheet, many of them from an empty brick
// into an occupied one or out of one into an empty one.
class PreintegrationSkippingTest : public PreintegrationTest {
protected:
    RendererOptions options() override {
        RendererOptions o;
        o.brick_voxels = 8;
        return o;
    }
};

TEST_F(PreintegrationSkippingTest, SegmentsIntoAndOutOfEmptyBricksKeepTheirContribution) {
    constexpr unsigned side = 48;
    std::vector<float> values(side * side * side, 0.0f);
    for (unsigned a = 4; a < side - 4; ++a) {
        for (unsigned b = 4; b < side - 4; ++b) {
            values[(std::size_t(b) * side + a) * side + 16] = 1.0f;  // first voxel of a brick
            values[(std::size_t(23) * side + b) * side + a] = 1.0f;  // last voxel of a brick
        }
    }
    auto made = volume::make_volume("sheets", glm::uvec3(side), glm::dvec3(1.0), values);
    ASSERT_TRUE(made.ok());
    use(*made);
    for (const scene::Mode mode : {scene::Mode::dvr, scene::Mode::reference}) {
        SCOPED_TRACE(scene::to_string(mode));
        auto request = steep_scene(mode);
        request.settings.width = 64;
        request.settings.height = 64;
        // Steps of ten voxels: a segment from a sheet's sample often ends in an empty brick, past
        // the rest of the sheet's brick and the one-voxel border of the next one. (At steps
        // shorter than that distance the case cannot arise: a segment that ends in an empty
        // brick then starts where every value the segment crosses is transparent too.)
        request.settings.sample_distance = 1.0 / 5.0;
        request.settings.preintegration = true;
        request.transfer_function = {
                "band",
                {{0.0, {1.0, 0.8, 0.5}}},
                {{0.0, 0.0}, {0.4, 0.0}, {0.41, 1.0}, {0.59, 1.0}, {0.6, 0.0}, {1.0, 0.0}}};
        request.settings.empty_space_skipping = true;
        const base::ImageRgbaF skipped = render(request);
        request.settings.empty_space_skipping = false;
        const base::ImageRgbaF marched = render(request);
        EXPECT_LE(compare(skipped, marched).max_error, 2.0 / 255.0);
        int drawn = 0;
        for (int y = 0; y < marched.height; ++y) {
            for (int x = 0; x < marched.width; ++x) {
                drawn += marched.pixel(x, y)[0] > 0.2f ? 1 : 0;
            }
        }
        EXPECT_GT(drawn, 200) << "the sheets' segments show";
    }
}

}  // namespace
}  // namespace penumbra::render
