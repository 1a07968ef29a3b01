// The GPU ray caster against the double-precision CPU renderer (server/reference), which
// computes the same integral independently. Tolerances are stated per case; on failure the
// actual, expected and difference images are written next to the test binary.

#include "dicom_writer.hpp"
#include "synthetic_volumes.hpp"

#include <penumbra/encode/encode.hpp>
#include <penumbra/imageio/compare.hpp>
#include <penumbra/reference/cpu_renderer.hpp>
#include <penumbra/render/renderer.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

#include <unistd.h>

namespace penumbra::render {
namespace {

struct Tolerance {
    double max_error;  // largest channel difference, [0, 1]
    double mean_error;
};

class RendererTest : public ::testing::Test {
protected:
    void SetUp() override {
        auto created = Renderer::create();
        ASSERT_TRUE(created.ok()) << created.error().to_string();
        renderer_ = std::move(created.value());
    }

    static scene::FrameRequest small_request(scene::Mode mode, int size = 64) {
        scene::FrameRequest request;
        request.camera = scene::orbit_camera(30.0, 20.0, 2.4);
        request.light.direction = scene::direction_from_angles(-60.0, 35.0);
        request.settings.mode = mode;
        request.settings.width = size;
        request.settings.height = size;
        request.settings.sample_distance = 1.0 / 128.0;
        request.settings.background = {0.2, 0.4, 0.6};
        request.transfer_function = {
                "test",
                {{0.0, {0.2, 0.4, 1.0}}, {0.5, {1.0, 0.6, 0.2}}, {1.0, {1.0, 1.0, 1.0}}},
                {{0.0, 0.0}, {0.2, 0.0}, {0.6, 0.1}, {1.0, 0.6}}};
        return request;
    }

    Frame render(const volume::Volume& volume, const scene::FrameRequest& request) {
        auto shared = std::make_shared<const volume::Volume>(volume);
        EXPECT_TRUE(renderer_->set_volume(shared).ok());
        auto frame = renderer_->render(request);
        EXPECT_TRUE(frame.ok()) << frame.error().to_string();
        return frame.ok() ? std::move(frame.value()) : Frame{};
    }

    // Renders on the GPU and the CPU and checks the difference.
    void expect_matches_cpu(const volume::Volume& volume, const scene::FrameRequest& request,
                            Tolerance tolerance, const std::string& label) {
        const Frame frame = render(volume, request);
        auto expected = reference::render_cpu(volume, request);
        ASSERT_TRUE(expected.ok()) << expected.error().to_string();
        const base::ImageRgbaF actual = base::to_rgba_f(frame.image);
        auto difference = imageio::compare_images(actual, *expected);
        ASSERT_TRUE(difference.ok());
        const bool ok = difference->max_error <= tolerance.max_error &&
                        difference->mean_error <= tolerance.mean_error;
        EXPECT_TRUE(ok) << label << ": max error " << difference->max_error << " (allowed "
                        << tolerance.max_error << "), mean error " << difference->mean_error
                        << " (allowed " << tolerance.mean_error << ")";
        if (!ok) {
            const auto dir = std::filesystem::current_path() / "golden";
            std::filesystem::create_directories(dir);
            (void)encode::write_image(dir / (label + "_actual.png"), frame.image);
            (void)encode::write_image(dir / (label + "_expected.png"), base::to_rgba8(*expected));
        }
    }

    std::unique_ptr<Renderer> renderer_;
};

// Float volumes are filtered in float on every GL implementation, so differences come from float
// vs double arithmetic and the final rounding to 8 bits: half a level plus a margin.
constexpr Tolerance float_volume{3.0 / 255.0, 0.6 / 255.0};

TEST_F(RendererTest, DvrMatchesCpuReference) {
    expect_matches_cpu(test::radial_volume(32), small_request(scene::Mode::dvr), float_volume,
                       "dvr");
}

TEST_F(RendererTest, DvrWithExtinctionCompositingMatchesCpuReference) {
    auto request = small_request(scene::Mode::dvr);
    request.settings.compositing = scene::Compositing::extinction;
    expect_matches_cpu(test::radial_volume(32), request, float_volume, "dvr_extinction");
}

TEST_F(RendererTest, PhongMatchesCpuReference) {
    expect_matches_cpu(test::radial_volume(32), small_request(scene::Mode::phong), float_volume,
                       "phong");
}

TEST_F(RendererTest, PhongWithPointLightMatchesCpuReference) {
    auto request = small_request(scene::Mode::phong);
    request.light.type = scene::LightType::point;
    request.light.position = {0.8, 0.9, 0.7};
    expect_matches_cpu(test::radial_volume(32), request, float_volume, "phong_point");
}

TEST_F(RendererTest, FragmentStageGivesTheComputeImage) {
    const volume::Volume volume = test::radial_volume(32);
    auto request = small_request(scene::Mode::phong);
    const Frame compute = render(volume, request);
    request.settings.stage = scene::RaycastStage::fragment;
    const Frame fragment = render(volume, request);
    EXPECT_EQ(fragment.report.stage, "fragment");
    auto difference = imageio::compare_images(base::to_rgba_f(compute.image),
                                              base::to_rgba_f(fragment.image));
    ASSERT_TRUE(difference.ok());
    EXPECT_LE(difference->max_error, 1.0 / 255.0 + 1e-6);
}

TEST_F(RendererTest, CameraInsideTheVolumeMatchesCpuReference) {
    auto request = small_request(scene::Mode::dvr);
    request.camera.eye = {0.05, 0.3, 0.1};
    request.camera.target = {0.0, -1.0, 0.0};
    request.camera.fov_y_degrees = 70.0;
    expect_matches_cpu(test::radial_volume(32), request, float_volume, "camera_inside");
}

TEST_F(RendererTest, AnisotropicVolumeKeepsItsShape) {
    volume::Volume volume = test::radial_volume(24);
    volume.spacing = {1.0, 1.0, 0.25};  // a flat disc-like box
    auto request = small_request(scene::Mode::dvr);
    request.camera = scene::orbit_camera(0.0, 0.0, 2.4);
    expect_matches_cpu(volume, request, float_volume, "anisotropic");
    // Seen from the side, the box is a quarter as tall as it is wide: rows far from the centre
    // show only background.
    const Frame frame = render(volume, request);
    const std::uint8_t* top = frame.image.pixel(32, 8);
    EXPECT_EQ(top[2], 153);
}

TEST_F(RendererTest, EmptyTransferFunctionGivesExactlyTheBackground) {
    auto request = small_request(scene::Mode::phong);
    request.transfer_function = {"empty", {}, {}};
    const Frame frame = render(test::radial_volume(16), request);
    for (int y = 0; y < frame.image.height; ++y) {
        for (int x = 0; x < frame.image.width; ++x) {
            const std::uint8_t* p = frame.image.pixel(x, y);
            ASSERT_EQ(p[0], 51);
            ASSERT_EQ(p[1], 102);
            ASSERT_EQ(p[2], 153);
        }
    }
}

TEST_F(RendererTest, FullyOpaqueTransferFunctionStaysFiniteAndMatchesCpu) {
    auto request = small_request(scene::Mode::phong);
    request.transfer_function = {"opaque", {{0.0, {0.9, 0.8, 0.7}}}, {{0.0, 1.0}}};
    request.settings.compositing = scene::Compositing::alpha;
    expect_matches_cpu(test::radial_volume(32), request, float_volume, "opaque_phong");
    request.settings.compositing = scene::Compositing::extinction;
    expect_matches_cpu(test::radial_volume(32), request, float_volume, "opaque_extinction");
}

TEST_F(RendererTest, Uint16AndUint8VolumesMatchCpuReference) {
    const volume::Volume radial = test::radial_volume(32);
    std::vector<std::byte> bytes16(radial.voxel_count() * 2);
    std::vector<std::byte> bytes8(radial.voxel_count());
    for (std::size_t i = 0; i < radial.voxel_count(); ++i) {
        float v = 0.0f;
        std::memcpy(&v, &radial.data[i * 4], 4);
        const auto v16 = static_cast<std::uint16_t>(std::lround(v * 60000.0f) + 1000);
        std::memcpy(&bytes16[i * 2], &v16, 2);
        bytes8[i] = static_cast<std::byte>(std::lround(v * 250.0f));
    }
    auto volume16 = volume::make_volume("u16", radial.dims, radial.spacing,
                                        volume::VoxelType::uint16, bytes16);
    auto volume8 = volume::make_volume("u8", radial.dims, radial.spacing, volume::VoxelType::uint8,
                                       bytes8);
    ASSERT_TRUE(volume16.ok() && volume8.ok());
    const auto request = small_request(scene::Mode::phong);
    expect_matches_cpu(*volume16, request, float_volume, "uint16");
    // Mesa's llvmpipe filters 8-bit textures with 8-bit interpolation weights, which moves
    // samples by up to 1/512 of a voxel step in value; the budget is therefore wider.
    expect_matches_cpu(*volume8, request, {8.0 / 255.0, 1.0 / 255.0}, "uint8");
}

// A CT as scanners write it: int16 stored values with a rescale intercept, kept as int16 on the
// GPU; the image matches the CPU reference, which reads the same real (Hounsfield) values.
TEST_F(RendererTest, Int16CtWithRescaleMatchesCpuReference) {
    const volume::Volume radial = test::radial_volume(32);
    std::vector<std::byte> bytes(radial.voxel_count() * 2);
    for (std::size_t i = 0; i < radial.voxel_count(); ++i) {
        float v = 0.0f;
        std::memcpy(&v, &radial.data[i * 4], 4);
        const auto stored = static_cast<std::int16_t>(std::lround(v * 4000.0f) - 1000);
        std::memcpy(&bytes[i * 2], &stored, 2);
    }
    auto ct = volume::make_volume("ct", radial.dims, radial.spacing, volume::VoxelType::int16,
                                  bytes, volume::Rescale{1.0, -1024.0});
    ASSERT_TRUE(ct.ok()) << ct.error().to_string();
    EXPECT_LT(ct->range.min, -1024.0);  // real values: the intercept applied
    expect_matches_cpu(*ct, small_request(scene::Mode::phong), float_volume, "int16");
}

TEST_F(RendererTest, CachesTheVolumeAndTransferFunctionUploads) {
    const volume::Volume volume = test::radial_volume(16);
    auto request = small_request(scene::Mode::dvr, 16);
    const auto names = [](const Frame& frame) {
        std::vector<std::string> out;
        for (const auto& pass : frame.report.passes) {
            out.push_back(pass.name);
        }
        return out;
    };
    auto shared = std::make_shared<const volume::Volume>(volume);
    ASSERT_TRUE(renderer_->set_volume(shared).ok());
    auto first = renderer_->render(request);
    ASSERT_TRUE(first.ok());
    EXPECT_EQ(names(*first),
              (std::vector<std::string>{"upload_volume", "brick_ranges", "transfer_function",
                                        "classify_bricks", "raycast", "readback"}));
    request.camera = scene::orbit_camera(100.0, -20.0, 2.0);
    auto second = renderer_->render(request);
    ASSERT_TRUE(second.ok());
    EXPECT_EQ(names(*second), (std::vector<std::string>{"raycast", "readback"}));
    request.transfer_function.opacities[3].alpha = 0.9;
    auto third = renderer_->render(request);
    ASSERT_TRUE(third.ok());
    // A TF change uploads the table and classifies the bricks again; their ranges stay.
    EXPECT_EQ(names(*third), (std::vector<std::string>{"transfer_function", "classify_bricks",
                                                       "raycast", "readback"}));
    EXPECT_GE(third->report.passes[1].wall_ms, 0.0);
}

TEST_F(RendererTest, RejectsBadRequestsWithoutBreaking) {
    auto request = small_request(scene::Mode::dvr, 16);
    auto no_volume = renderer_->render(request);
    ASSERT_FALSE(no_volume.ok());
    EXPECT_EQ(no_volume.error().code, base::ErrorCode::no_volume);
    ASSERT_TRUE(
            renderer_->set_volume(std::make_shared<const volume::Volume>(test::radial_volume(8)))
                    .ok());
    request.settings.sample_distance = -1.0;
    EXPECT_EQ(renderer_->render(request).error().where, "sample_distance");
    request = small_request(scene::Mode::sbrc, 16);
    request.settings.light_buffer.slices = renderer_->info().max_array_texture_layers + 1;
    EXPECT_EQ(renderer_->render(request).error().where, "light_buffer.slices");
    request = small_request(scene::Mode::sbrc, 16);
    request.light.type = scene::LightType::point;
    request.light.position = {0.1, 0.0, 0.0};  // inside the volume
    EXPECT_EQ(renderer_->render(request).error().code, base::ErrorCode::unsupported_light);
    request = small_request(scene::Mode::dvr, 16);
    EXPECT_TRUE(renderer_->render(request).ok());
}

}  // namespace
}  // namespace penumbra::render

namespace penumbra::render {
namespace {

// The real Colin27 head: seen from the front with the skin preset, the face covers the middle of
// the image in skin tones and the corners stay background.
TEST(RendererRealData, RendersTheCh2HeadFromTheFront) {
    auto loaded = volume::load_volume("/usr/share/mricron/templates/ch2.nii.gz");
    ASSERT_TRUE(loaded.ok()) << loaded.error().to_string()
                             << " (the install step gets it from Debian's mricron-data)";
    auto renderer = Renderer::create();
    ASSERT_TRUE(renderer.ok()) << renderer.error().to_string();
    ASSERT_TRUE((*renderer)->set_volume(std::make_shared<const volume::Volume>(*loaded)).ok());
    scene::FrameRequest request;
    request.camera = scene::orbit_camera(0.0, 0.0, 2.6);
    request.light.direction = scene::direction_from_angles(0.0, 30.0);
    request.settings.mode = scene::Mode::phong;
    request.settings.width = 64;
    request.settings.height = 64;
    request.transfer_function = scene::preset("mri_skin").value();
    auto frame = (*renderer)->render(request);
    ASSERT_TRUE(frame.ok()) << frame.error().to_string();
    int covered = 0;
    double red = 0.0;
    double blue = 0.0;
    for (int y = 0; y < 64; ++y) {
        for (int x = 0; x < 64; ++x) {
            const std::uint8_t* p = frame->image.pixel(x, y);
            if (p[0] + p[1] + p[2] > 0) {
                ++covered;
                red += p[0];
                blue += p[2];
            }
        }
    }
    EXPECT_GT(covered, 64 * 64 / 4);
    EXPECT_LT(covered, 64 * 64 * 9 / 10);
    EXPECT_GT(red, 1.2 * blue);  // skin tones
    EXPECT_EQ(frame->image.pixel(0, 0)[0], 0);
    EXPECT_GT(frame->image.pixel(32, 32)[0], 40);
}

// A DICOM series written from a box of the ch2 head renders exactly like the same voxels handed
// over in memory, and shows something: the loader's grid, spacing and values reach the GPU.
TEST(RendererRealData, DicomSeriesRendersLikeTheSameVoxelsInMemory) {
    const glm::uvec3 dims{64, 48, 24};
    volume::fixtures::SeriesSpec spec;
    spec.dims = dims;
    spec.spacing = {2.0, 2.5, 3.0};
    const auto words = volume::fixtures::ch2_box({58, 60, 60}, dims);
    const auto folder = std::filesystem::temp_directory_path() /
                        ("penumbra-dicom-render-" + std::to_string(::getpid()));
    volume::fixtures::write_series(folder, spec, words);
    auto loaded = volume::load_volume(folder);
    std::filesystem::remove_all(folder);
    ASSERT_TRUE(loaded.ok()) << loaded.error().to_string();
    std::vector<std::byte> bytes(words.size() * 2);
    std::memcpy(bytes.data(), words.data(), bytes.size());
    auto in_memory = volume::make_volume("box", dims, spec.spacing, volume::VoxelType::uint16,
                                         std::move(bytes));
    ASSERT_TRUE(in_memory.ok());
    // The series is axial LPS: the same voxels lie the same way round when they carry its axes.
    in_memory->axes = loaded->axes;
    in_memory->origin = loaded->origin;

    auto renderer = Renderer::create();
    ASSERT_TRUE(renderer.ok()) << renderer.error().to_string();
    scene::FrameRequest request;
    request.camera = scene::orbit_camera(30.0, 20.0, 2.6);
    request.light.direction = scene::direction_from_angles(-30.0, 30.0);
    request.settings.mode = scene::Mode::phong;
    request.settings.width = 64;
    request.settings.height = 64;
    request.transfer_function = scene::preset("mri_brain").value();
    const auto render = [&](const volume::Volume& volume) {
        EXPECT_TRUE((*renderer)->set_volume(std::make_shared<const volume::Volume>(volume)).ok());
        auto frame = (*renderer)->render(request);
        EXPECT_TRUE(frame.ok()) << frame.error().to_string();
        return frame.ok() ? std::move(frame.value()) : Frame{};
    };
    const Frame from_dicom = render(*loaded);
    const Frame from_memory = render(*in_memory);
    ASSERT_EQ(from_dicom.image.width, 64);
    ASSERT_EQ(from_memory.image.width, 64);
    int covered = 0;
    for (int y = 0; y < 64; ++y) {
        for (int x = 0; x < 64; ++x) {
            const std::uint8_t* p = from_dicom.image.pixel(x, y);
            covered += p[0] + p[1] + p[2] > 0 ? 1 : 0;
            ASSERT_EQ(std::memcmp(p, from_memory.image.pixel(x, y), 4), 0)
                    << "pixel " << x << "," << y;
        }
    }
    EXPECT_GT(covered, 64 * 64 / 10);
}

}  // namespace
}  // namespace penumbra::render
