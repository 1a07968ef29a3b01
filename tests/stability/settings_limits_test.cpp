// Settings at and beyond their limits: tiny and huge sample distances, one slice and the GL layer
// limit, light-buffer resolutions of 1 and GL_MAX_TEXTURE_SIZE, values past the limits (which
// must give an Error naming the field), fully opaque and fully transparent TFs, and the darkening
// compensation from 0 to its maximum of 1000.

#include "stability.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace penumbra::stability {
namespace {

using Builder = scene::LightBufferBuilder;

const std::vector<scene::Mode> slicing_modes =
        modes_where([](const scene::ModeInfo& row) { return scene::uses_light_view(row.mode); });

class SettingsTest : public ModeTest {
protected:
    void SetUp() override {
        ModeTest::SetUp();
        use(float_volume(glm::uvec3(16), glm::dvec3(1.0), radial));
    }
};

// The modes that slice the volume toward the light.
class SlicingModeTest : public SettingsTest {};

// Requests that only differ in what validation must reject.
class LimitsTest : public StabilityTest {
protected:
    void SetUp() override {
        StabilityTest::SetUp();
        use(float_volume(glm::uvec3(8), glm::dvec3(1.0), radial));
    }

    // Every mode rejects `request` with an Error whose `where` is `field`.
    void expect_rejected(scene::FrameRequest request, const std::string& field) {
        for (const scene::Mode mode : all_modes) {
            request.settings.mode = mode;
            auto frame = renderer_->render(request);
            ASSERT_FALSE(frame.ok()) << describe(request) << " was accepted";
            EXPECT_EQ(frame.error().where, field) << frame.error().to_string();
            EXPECT_FALSE(frame.error().message.empty());
        }
    }
};

// 1/16384 is the smallest sample distance validation accepts: 28 000 samples on the longest ray,
// beyond what llvmpipe lets one shader invocation loop, so the compute ray caster marches in
// chunks. Cost grows with it (and with its square for the reference's shadow rays), hence 4x4
// images, 1/8192 for the modes that do more work per sample, and for the reference 1/512, the
// finest distance DESIGN.md names, on 8x8 pixels. A faint medium (opacity 0.05 per 1/256) keeps
// rays and shadow rays from terminating early, so every sample is marched. Opacity correction
// makes the integral independent of the step, so the modes without a CPU twin must give the
// image they give at 1/1024, up to discretisation (measured: 0 levels wherever every sample is
// marched; 3 allowed).
TEST_F(SettingsTest, TinySampleDistanceGivesASaneImage) {
    for_each_mode(all_modes, [&] {
        auto request = base_request(mode(), 4);
        request.camera = scene::orbit_camera(30.0, 20.0, 1.6);
        request.settings.opacity_unit_distance = 1.0 / 256.0;
        request.transfer_function.opacities.back().alpha = 0.05;
        switch (mode()) {
            case scene::Mode::dvr:
            case scene::Mode::sbrc:
                request.settings.sample_distance = 1.0 / 16384.0;
                break;
            case scene::Mode::reference:
                request.settings.sample_distance = 1.0 / 512.0;
                request.settings.width = 8;
                request.settings.height = 8;
                break;
            case scene::Mode::phong:
            case scene::Mode::half_angle:
            case scene::Mode::sbrc_shell:
            case scene::Mode::sbrc_cone:
                request.settings.sample_distance = 1.0 / 8192.0;
                break;
        }
        for (const auto compositing : {scene::Compositing::alpha, scene::Compositing::extinction}) {
            request.settings.compositing = compositing;
            auto frame = render_and_check(request);
            if (!frame || has_cpu_reference(mode())) {
                continue;
            }
            auto coarse_request = request;
            coarse_request.settings.sample_distance = 1.0 / 1024.0;
            auto coarse = render(coarse_request);
            ASSERT_TRUE(coarse.has_value());
            int worst = 0;
            for (std::size_t i = 0; i < frame->image.pixels.size(); ++i) {
                worst = std::max(worst, std::abs(int{frame->image.pixels[i]} -
                                                 int{coarse->image.pixels[i]}));
            }
            EXPECT_LE(worst, 3) << describe(request) << ": differs from the image at 1/1024";
        }
    });
}

TEST_F(SettingsTest, HugeSampleDistanceGivesASaneImage) {
    for_each_mode(all_modes, [&] {
        for (const double distance : {0.25, 1.0, 2.0}) {
            auto request = base_request(mode(), 16);
            request.settings.sample_distance = distance;
            render_and_check(request);
            request.settings.phong = true;
            request.settings.compositing = scene::Compositing::extinction;
            render_and_check(request);
        }
    });
}

TEST_F(LimitsTest, SampleDistanceOutsideItsRangeIsRejected) {
    for (const double distance :
         {0.0, -1.0 / 64.0, 1e-7, 2.5, std::nan(""), std::numeric_limits<double>::infinity()}) {
        auto request = base_request(scene::Mode::dvr, 8);
        request.settings.sample_distance = distance;
        SCOPED_TRACE("sample distance " + std::to_string(distance));
        expect_rejected(request, "sample_distance");
    }
}

TEST_F(SlicingModeTest, OneSliceGivesASaneImage) {
    for_each_mode(slicing_modes, [&] {
        for (const Builder builder : {Builder::multi_slice, Builder::per_slice}) {
            for (const int resolution : {1, 24}) {
                auto request = base_request(mode(), 16);
                request.settings.light_buffer.slices = 1;
                request.settings.light_buffer.resolution = resolution;
                request.settings.light_buffer.builder = builder;
                render_and_check(request);
                request.light.direction = {0.0, 0.0, 1.0};  // the one slice is the box's mid-plane
                request.settings.phong = true;
                render_and_check(request);
            }
        }
    });
}

TEST_F(SlicingModeTest, SlicesAtTheLayerLimitGiveASaneImage) {
    for_each_mode(slicing_modes, [&] {
        const int limit = renderer_->info().max_array_texture_layers;
        ASSERT_GE(limit, 256);  // GL 4.5 guarantees 2048
        for (const Builder builder : {Builder::multi_slice, Builder::per_slice}) {
            auto request = base_request(mode(), 16);
            request.settings.light_buffer.slices = limit;
            request.settings.light_buffer.resolution = 8;
            request.settings.light_buffer.builder = builder;
            render_and_check(request);
        }
    });
}

TEST_F(LimitsTest, SlicesOutsideOneToTheLayerLimitAreRejected) {
    for (const int slices :
         {0, -1, renderer_->info().max_array_texture_layers + 1, std::numeric_limits<int>::max()}) {
        auto request = base_request(scene::Mode::sbrc, 8);
        request.settings.light_buffer.slices = slices;
        SCOPED_TRACE("slices " + std::to_string(slices));
        expect_rejected(request, "light_buffer.slices");
    }
}

TEST_F(SlicingModeTest, LightBufferResolutionOneGivesASaneImage) {
    for_each_mode(slicing_modes, [&] {
        for (const Builder builder : {Builder::multi_slice, Builder::per_slice}) {
            for (const int slices : {2, 64}) {
                auto request = base_request(mode(), 16);
                request.settings.light_buffer.resolution = 1;
                request.settings.light_buffer.slices = slices;
                request.settings.light_buffer.builder = builder;
                render_and_check(request);
            }
        }
    });
}

// GL_MAX_TEXTURE_SIZE texels a side (16384 on llvmpipe: 512 MiB of half floats per layer) with
// one slice, since more would exceed any GPU's memory. The per-slice builder and half-angle
// slicing allocate and fill such buffers in seconds on llvmpipe; the multi-slice builder's
// dispatch over 2.7e8 texels takes about 20 s there, so it is exercised at smaller sizes only.
// The buffer is too large to read back; the frame is checked.
TEST_F(StabilityTest, LightBufferResolutionAtTheTextureLimitGivesASaneImage) {
    use(float_volume(glm::uvec3(16), glm::dvec3(1.0), radial));
    const int limit = renderer_->info().max_texture_size;
    for (const scene::Mode mode : {scene::Mode::sbrc, scene::Mode::half_angle}) {
        auto request = base_request(mode, 16);
        request.settings.light_buffer.slices = 1;
        request.settings.light_buffer.resolution = limit;
        request.settings.light_buffer.builder = Builder::per_slice;
        CheckOptions options;
        options.check_light_buffer = false;
        render_and_check(request, options);
    }
}

TEST_F(LimitsTest, LightBufferResolutionOutsideOneToTheTextureLimitIsRejected) {
    for (const int resolution : {0, -8, renderer_->info().max_texture_size + 1}) {
        auto request = base_request(scene::Mode::sbrc, 8);
        request.settings.light_buffer.resolution = resolution;
        SCOPED_TRACE("resolution " + std::to_string(resolution));
        expect_rejected(request, "light_buffer.resolution");
    }
}

TEST_F(LimitsTest, ImageSizeOutsideOneToTheTextureLimitIsRejected) {
    for (const auto& [width, height] : {std::pair{0, 8}, std::pair{8, -1},
                                        std::pair{renderer_->info().max_texture_size + 1, 1}}) {
        auto request = base_request(scene::Mode::dvr, 8);
        request.settings.width = width;
        request.settings.height = height;
        SCOPED_TRACE(std::to_string(width) + "x" + std::to_string(height));
        expect_rejected(request, "size");
    }
}

TEST_F(LimitsTest, CompensationOutsideZeroToAThousandIsRejected) {
    for (const double compensation : {-1.0, 1000.5, std::nan("")}) {
        auto request = base_request(scene::Mode::sbrc, 8);
        request.settings.light_buffer.compensation = compensation;
        SCOPED_TRACE("compensation " + std::to_string(compensation));
        expect_rejected(request, "light_buffer.compensation");
    }
}

TEST_F(LimitsTest, SlabSamplesOutsideZeroToTheMaximumAreRejected) {
    for (const int samples : {-1, scene::kMaxSlabSamples + 1, 1 << 30}) {
        auto request = base_request(scene::Mode::sbrc, 8);
        request.settings.light_buffer.slab_samples = samples;
        SCOPED_TRACE("slab samples " + std::to_string(samples));
        expect_rejected(request, "light_buffer.slab_samples");
    }
}

// A rejected request must leave no half-changed state behind.
TEST_F(LimitsTest, RejectedRequestsLeaveTheNextFrameUnchanged) {
    for (const scene::Mode mode : all_modes) {
        const auto good = base_request(mode, 12);
        auto before = render(good);
        ASSERT_TRUE(before.has_value());
        auto bad = good;
        bad.settings.light_buffer.slices = renderer_->info().max_array_texture_layers + 1;
        bad.transfer_function = opaque_tf();
        bad.light.direction = {0.0, 0.0, 1.0};
        EXPECT_FALSE(renderer_->render(bad).ok());
        bad = good;
        bad.settings.sample_distance = 0.0;
        bad.settings.width = 7;
        EXPECT_FALSE(renderer_->render(bad).ok());
        auto after = render(good);
        ASSERT_TRUE(after.has_value());
        EXPECT_EQ(before->image.pixels, after->image.pixels) << scene::to_string(mode);
        if (scene::uses_light_buffer(mode)) {
            EXPECT_EQ(after->report.light_buffer, render::LightBufferState::reused)
                    << scene::to_string(mode);
        }
    }
}

TEST_F(SettingsTest, OpaqueTransferFunctionGivesASaneImage) {
    for_each_mode(all_modes, [&] {
        for (const auto compositing : {scene::Compositing::alpha, scene::Compositing::extinction}) {
            for (const bool phong : {false, true}) {
                for (const double compensation : {0.0, 1000.0}) {
                    auto request = base_request(mode(), 16);
                    request.transfer_function = opaque_tf();
                    request.settings.compositing = compositing;
                    request.settings.phong = phong;
                    request.settings.light_buffer.compensation = compensation;
                    CheckOptions options;
                    options.min_visible_fraction = 0.2;
                    render_and_check(request, options);
                }
            }
        }
    });
}

// Nothing absorbs or emits: the background exactly, and a light buffer of ones.
TEST_F(SettingsTest, TransparentTransferFunctionGivesExactlyTheBackground) {
    for_each_mode(all_modes, [&] {
        const scene::TransferFunction empty{"empty", {}, {}};
        for (const auto& tf : {transparent_tf(), empty}) {
            for (const Builder builder : {Builder::multi_slice, Builder::per_slice}) {
                auto request = base_request(mode(), 16);
                request.transfer_function = tf;
                request.settings.phong = true;
                request.settings.light_buffer.builder = builder;
                request.settings.light_buffer.compensation = 1000.0;
                CheckOptions options;
                options.expect_background = true;
                render_and_check(request, options);
                if (scene::uses_light_buffer(mode())) {
                    auto buffer = renderer_->read_light_buffer();
                    ASSERT_TRUE(buffer.ok());
                    const auto dark = std::count_if(buffer->values.begin(), buffer->values.end(),
                                                    [](float v) { return v != 1.0f; });
                    EXPECT_EQ(dark, 0) << "texels below 1 under a transparent TF";
                }
            }
        }
    });
}

// Compensation (1 + a)^n only ever gives light back (capped at none absorbed), so raising n never
// darkens a pixel or a light-buffer texel, for any n up to the maximum of 1000.
TEST_F(SlicingModeTest, CompensationFromZeroToAThousandNeverDarkens) {
    for_each_mode(slicing_modes, [&] {
        auto request = base_request(mode(), 16);
        request.transfer_function.opacities.back().alpha = 0.6;  // deep shadows to compensate
        std::optional<render::Frame> previous;
        double previous_mean = 0.0;
        for (const double compensation : {0.0, 0.5, 1.0, 4.0, 10.0, 100.0, 1000.0}) {
            SCOPED_TRACE("compensation " + std::to_string(compensation));
            request.settings.light_buffer.compensation = compensation;
            auto frame = render_and_check(request);
            ASSERT_TRUE(frame.has_value());
            if (previous) {
                for (std::size_t i = 0; i < frame->image.pixels.size(); ++i) {
                    ASSERT_GE(int{frame->image.pixels[i]} + 1, int{previous->image.pixels[i]})
                            << "pixel " << i / 4 << " channel " << i % 4 << " darkened";
                }
            }
            if (scene::uses_light_buffer(mode())) {
                auto buffer = renderer_->read_light_buffer();
                ASSERT_TRUE(buffer.ok());
                double sum = 0.0;
                for (const float v : buffer->values) {
                    sum += v;
                }
                const double mean = sum / static_cast<double>(buffer->values.size());
                EXPECT_GE(mean + 1e-4, previous_mean);
                previous_mean = mean;
            }
            previous = std::move(frame);
        }
        // The shadows were deep and compensation did lift them.
        if (scene::uses_light_buffer(mode())) {
            EXPECT_GT(previous_mean, 0.95);
        }
    });
}

// The modes without a light buffer ignore compensation: it is the paper's correction for the
// light buffer's darkening, and the reference must stay the ground truth.
TEST_F(StabilityTest, CompensationDoesNotChangeModesWithoutLightSlicing) {
    use(float_volume(glm::uvec3(16), glm::dvec3(1.0), radial));
    for (const scene::Mode mode : {scene::Mode::dvr, scene::Mode::phong, scene::Mode::reference}) {
        auto request = base_request(mode, 16);
        request.settings.phong = true;
        auto plain = render_and_check(request);
        request.settings.light_buffer.compensation = 1000.0;
        auto compensated = render_and_check(request);
        ASSERT_TRUE(plain && compensated);
        EXPECT_EQ(plain->image.pixels, compensated->image.pixels) << scene::to_string(mode);
    }
}

}  // namespace
}  // namespace penumbra::stability
