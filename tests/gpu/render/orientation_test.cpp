// The volume's orientation (Volume::axes): one head stored RAS, LAS, LPS, with its index axes in a
// sagittal order and rotated obliquely renders the same anatomy from the same camera in every
// mode, with the same shadows, on the GPU and in the CPU reference; ignoring the orientation
// would show a mirror image, which these comparisons catch. The same holds for DICOM series
// written axial, sagittal and coronal from one head and read back through the loader: Image
// Orientation and Position (Patient) place each the same way.

#include "dicom_writer.hpp"

#include <penumbra/imageio/compare.hpp>
#include <penumbra/reference/cpu_renderer.hpp>
#include <penumbra/render/renderer.hpp>

#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

namespace penumbra::render {
namespace {

// A smooth, asymmetric head in RAS millimetres around its centre: a soft ellipsoid with a nose
// (anterior), an ear on the right side only, and a lump on the top toward the left and back.
// The ear sticks out of the head's side by about 10 mm.
double head(glm::dvec3 p) {
    const auto blob = [&](glm::dvec3 centre, double radius, double peak) {
        const double d = glm::length(p - centre) / radius;
        return peak * std::max(0.0, 1.0 - d * d);
    };
    const double r = glm::length(p / glm::dvec3(30.0, 36.0, 33.0));
    const double skull = 0.6 * std::clamp((1.0 - r) * 4.0, 0.0, 1.0);
    return std::max({skull, blob({0.0, 34.0, -4.0}, 9.0, 0.75), blob({32.0, 0.0, 2.0}, 12.0, 1.0),
                     blob({-12.0, -14.0, 29.0}, 10.0, 0.75)});
}

// The head sampled at the voxel centres of a grid whose index axes point along `axes` (columns,
// RAS), centred on the head.
volume::Volume head_volume(const std::string& name, const glm::dmat3& axes, glm::uvec3 dims,
                           glm::dvec3 spacing) {
    const glm::dvec3 extent = glm::dvec3(dims) * spacing;
    std::vector<float> values;
    values.reserve(static_cast<std::size_t>(dims.x) * dims.y * dims.z);
    for (unsigned k = 0; k < dims.z; ++k) {
        for (unsigned j = 0; j < dims.y; ++j) {
            for (unsigned i = 0; i < dims.x; ++i) {
                const glm::dvec3 index_position =
                        (glm::dvec3(i, j, k) + 0.5) * spacing - 0.5 * extent;
                values.push_back(static_cast<float>(head(axes * index_position)));
            }
        }
    }
    auto made = volume::make_volume(name, dims, spacing, values);
    EXPECT_TRUE(made.ok());
    volume::Volume out = std::move(made.value());
    // The same range for every storage, so the TF classifies every copy alike.
    out.range = {0.0, 1.0};
    out.axes = axes;
    return out;
}

glm::dmat3 columns(glm::dvec3 i, glm::dvec3 j, glm::dvec3 k) {
    return glm::dmat3(i, j, k);
}

constexpr glm::dvec3 right{1, 0, 0};
constexpr glm::dvec3 anterior{0, 1, 0};
constexpr glm::dvec3 superior{0, 0, 1};

// RAS dims and spacing: 78 x 96 x 90 mm; the longest side (96 mm, anterior) sets the box's scale,
// so every storage below keeps it.
constexpr glm::uvec3 ras_dims{26, 40, 25};
constexpr glm::dvec3 ras_spacing{3.0, 2.4, 3.6};

struct Storage {
    std::string name;
    volume::Volume volume;
    double tolerance;  // RMS against the RAS image: rounding for axis permutations, resampling
                       // for the oblique grid
};

std::vector<Storage> storages() {
    std::vector<Storage> out;
    out.push_back({"RAS",
                   head_volume("RAS", columns(right, anterior, superior), ras_dims, ras_spacing),
                   0.0});
    out.push_back({"LAS",
                   head_volume("LAS", columns(-right, anterior, superior), ras_dims, ras_spacing),
                   0.005});
    out.push_back({"LPS",
                   head_volume("LPS", columns(-right, -anterior, superior), ras_dims, ras_spacing),
                   0.005});
    // A sagittal series: rows run anterior, columns superior, slices toward the right.
    out.push_back(
            {"ASR",
             head_volume("ASR", columns(anterior, superior, right), {40, 25, 26}, {2.4, 3.6, 3.0}),
             0.005});
    // Oblique: a cube grid of the same longest side, rotated 35 degrees about a skew axis.
    const glm::dmat3 oblique(
            glm::rotate(glm::dmat4(1.0), glm::radians(35.0), glm::normalize(glm::dvec3(1, 2, 2))));
    out.push_back(
            {"oblique", head_volume("oblique", oblique, {32, 32, 32}, glm::dvec3(3.0)), 0.04});
    return out;
}

scene::FrameRequest head_request(scene::Mode mode, const scene::Camera& camera, int size) {
    scene::FrameRequest request;
    request.camera = camera;
    // From the patient's left, front and above: the ear and the nose cast shadows onto the head.
    request.light.direction = scene::direction_from_angles(-60.0, 40.0);
    request.light.ambient = 0.15;
    request.settings.mode = mode;
    request.settings.width = size;
    request.settings.height = size;
    // The reference marches a shadow ray from every sample: coarser, to stay quick.
    request.settings.sample_distance = mode == scene::Mode::reference ? 1.0 / 64.0 : 1.0 / 128.0;
    request.settings.light_buffer.slices = 64;
    request.settings.light_buffer.resolution = 64;
    request.settings.background = {0.0, 0.0, 0.0};
    request.transfer_function = {
            "head",
            {{0.0, {1.0, 1.0, 1.0}}, {0.8, {1.0, 1.0, 1.0}}, {1.0, {1.0, 0.1, 0.1}}},
            {{0.0, 0.0}, {0.3, 0.0}, {0.6, 0.15}, {0.75, 0.8}, {1.0, 1.0}}};
    return request;
}

double rms(const base::ImageRgbaF& a, const base::ImageRgbaF& b) {
    auto difference = imageio::compare_images(a, b);
    EXPECT_TRUE(difference.ok());
    return difference.ok() ? difference->rms_error : 1.0;
}

// How many pixels show the head in the left and in the right half of the image.
std::pair<int, int> coverage_left_right(const base::ImageRgbaF& image) {
    int left = 0;
    int right_half = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const float* p = image.pixel(x, y);
            if (std::max({p[0], p[1], p[2]}) > 0.1f) {
                ++(x < image.width / 2 ? left : right_half);
            }
        }
    }
    return {left, right_half};
}

class OrientationTest : public ::testing::TestWithParam<scene::Mode> {
protected:
    void SetUp() override {
        auto created = Renderer::create();
        ASSERT_TRUE(created.ok()) << created.error().to_string();
        renderer_ = std::move(created.value());
    }

    base::ImageRgbaF render(const volume::Volume& volume, const scene::FrameRequest& request) {
        volumes_.push_back(std::make_shared<const volume::Volume>(volume));
        EXPECT_TRUE(renderer_->set_volume(volumes_.back()).ok());
        auto frame = renderer_->render(request);
        EXPECT_TRUE(frame.ok()) << frame.error().to_string();
        return frame.ok() ? base::to_rgba_f(frame->image) : base::ImageRgbaF(1, 1);
    }

    std::unique_ptr<Renderer> renderer_;
    std::vector<std::shared_ptr<const volume::Volume>> volumes_;
};

TEST_P(OrientationTest, EveryStorageRendersTheSameAnatomy) {
    const auto stored = storages();
    // From the front and from an angle that shows three faces of the box.
    for (const auto& camera :
         {scene::orbit_camera(0.0, 0.0, 2.6), scene::orbit_camera(35.0, 25.0, 2.6)}) {
        const auto request = head_request(GetParam(), camera, 48);
        const base::ImageRgbaF ras = render(stored[0].volume, request);
        for (std::size_t s = 1; s < stored.size(); ++s) {
            SCOPED_TRACE(stored[s].name);
            const base::ImageRgbaF image = render(stored[s].volume, request);
            const double error = rms(image, ras);
            EXPECT_LT(error, stored[s].tolerance);
            // Drawn as stored, ignoring the orientation, the head is mirrored or turned: far off.
            volume::Volume as_stored = stored[s].volume;
            as_stored.axes = glm::dmat3(1.0);
            const double ignored = rms(render(as_stored, request), ras);
            EXPECT_GT(ignored, 0.05);
            EXPECT_GT(ignored, 2.0 * error);
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Modes, OrientationTest,
                         ::testing::Values(scene::Mode::dvr, scene::Mode::phong, scene::Mode::sbrc,
                                           scene::Mode::sbrc_shell, scene::Mode::sbrc_cone,
                                           scene::Mode::half_angle, scene::Mode::reference),
                         [](const ::testing::TestParamInfo<scene::Mode>& mode) {
                             return std::string(scene::to_string(mode.param));
                         });

// The patient's right lies on the viewer's left when the camera looks at the face: the ear shows
// on the left.
TEST_F(OrientationTest, RightEarShowsOnTheLeftFromTheFront) {
    for (const auto& storage : storages()) {
        SCOPED_TRACE(storage.name);
        const auto image =
                render(storage.volume,
                       head_request(scene::Mode::dvr, scene::orbit_camera(0.0, 0.0, 2.6), 64));
        const auto [left, right_half] = coverage_left_right(image);
        EXPECT_GT(left, right_half + 30);
    }
}

// A sheared transform (a gantry tilt) cannot be drawn as an oriented box: refused, not drawn wrong.
TEST_F(OrientationTest, ShearedAxesAreRefusedWithAClearMessage) {
    volume::Volume sheared = storages()[0].volume;
    sheared.axes[2] = glm::normalize(glm::dvec3(0.0, 0.3, 1.0));  // slices tilted toward anterior
    const auto shared = std::make_shared<const volume::Volume>(sheared);
    const auto status = renderer_->set_volume(shared);
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.error().code, base::ErrorCode::unsupported_orientation);
    EXPECT_NE(status.error().message.find("sheared"), std::string::npos);
    const auto cpu = reference::render_cpu(
            sheared, head_request(scene::Mode::dvr, scene::orbit_camera(0.0, 0.0, 2.6), 8));
    ASSERT_FALSE(cpu.ok());
    EXPECT_EQ(cpu.error().code, base::ErrorCode::unsupported_orientation);
}

// A DICOM series of the head: the slices of the plane whose row and column directions are
// given (DICOM's LPS), spaced 3 mm every way, and centred on the head like the RAS grid above,
// so that every plane samples the same points and differs only in how it stores them.
struct DicomPlane {
    std::string name;
    glm::dvec3 row;     // LPS
    glm::dvec3 column;  // LPS
};

constexpr double dicom_spacing = 3.0;

// The head's extent along L, P and S in voxels of 3 mm (78 x 96 x 90 mm, as the RAS grid).
constexpr glm::uvec3 lps_voxels{26, 32, 30};

// Writes the series into `folder` and returns what the loader reads from it.
volume::Volume write_and_load_dicom(const DicomPlane& plane, const std::filesystem::path& folder) {
    const glm::dvec3 normal = glm::cross(plane.row, plane.column);
    const auto voxels_along = [](glm::dvec3 direction) {
        return static_cast<unsigned>(
                std::lround(glm::length(glm::abs(direction) * glm::dvec3(lps_voxels))));
    };
    volume::fixtures::SeriesSpec spec;
    spec.dims = {voxels_along(plane.row), voxels_along(plane.column), voxels_along(normal)};
    spec.spacing = glm::dvec3(dicom_spacing);
    spec.orientation = {plane.row.x,    plane.row.y,    plane.row.z,
                        plane.column.x, plane.column.y, plane.column.z};
    // The first voxel's centre: half the grid back from the head's centre along each axis.
    spec.origin = -0.5 * dicom_spacing *
                  (double(spec.dims.x - 1) * plane.row + double(spec.dims.y - 1) * plane.column +
                   double(spec.dims.z - 1) * normal);
    std::vector<std::uint16_t> words;
    for (unsigned k = 0; k < spec.dims.z; ++k) {
        for (unsigned j = 0; j < spec.dims.y; ++j) {
            for (unsigned i = 0; i < spec.dims.x; ++i) {
                const glm::dvec3 lps = spec.origin + dicom_spacing * (double(i) * plane.row +
                                                                      double(j) * plane.column +
                                                                      double(k) * normal);
                words.push_back(static_cast<std::uint16_t>(
                        std::lround(1000.0 * head(volume::lps_to_ras(lps)))));
            }
        }
    }
    volume::fixtures::write_series(folder, spec, words);
    auto loaded = volume::load_volume(folder);
    EXPECT_TRUE(loaded.ok()) << loaded.error().to_string();
    if (!loaded.ok()) {
        return {};
    }
    volume::Volume out = std::move(loaded.value());
    EXPECT_EQ(out.dims, spec.dims);
    out.range = {0.0, 1000.0};  // the head's values, as the TF positions read them
    return out;
}

class DicomOrientationTest : public OrientationTest {
protected:
    void SetUp() override {
        OrientationTest::SetUp();
        folder_ = std::filesystem::temp_directory_path() /
                  ("penumbra-dicom-orientation-" + std::to_string(::getpid()));
        std::filesystem::remove_all(folder_);
    }

    void TearDown() override {
        std::error_code ec;
        std::filesystem::remove_all(folder_, ec);
    }

    std::filesystem::path folder_;
};

// Axial (rows toward the patient's left, columns posterior), sagittal (rows posterior, columns
// inferior, slices toward the right) and coronal (rows left, columns inferior, slices posterior)
// series of one head render alike from each named view, in a ray-cast and a shadowing mode; drawn
// ignoring their orientation, the sagittal and coronal ones would be turned.
TEST_F(DicomOrientationTest, AxialSagittalAndCoronalSeriesRenderTheSameAnatomy) {
    const std::vector<DicomPlane> planes{{"axial", {1, 0, 0}, {0, 1, 0}},
                                         {"sagittal", {0, 1, 0}, {0, 0, -1}},
                                         {"coronal", {1, 0, 0}, {0, 0, -1}}};
    std::vector<volume::Volume> series;
    for (const DicomPlane& plane : planes) {
        series.push_back(write_and_load_dicom(plane, folder_ / plane.name));
        ASSERT_FALSE(HasFailure()) << plane.name;
    }
    EXPECT_EQ(volume::orientation_code(series[0].axes), "LPS");
    EXPECT_EQ(volume::orientation_code(series[1].axes), "PIR");
    EXPECT_EQ(volume::orientation_code(series[2].axes), "LIP");
    for (const scene::Mode mode : {scene::Mode::dvr, scene::Mode::sbrc}) {
        for (const scene::View view :
             {scene::View::anterior, scene::View::left, scene::View::superior}) {
            SCOPED_TRACE(std::string(scene::to_string(mode)) + " from " + scene::to_string(view));
            const auto request = head_request(mode, scene::view_camera(view, 2.6), 64);
            const base::ImageRgbaF axial = render(series[0], request);
            if (mode == scene::Mode::dvr && view == scene::View::anterior) {
                const auto [left, right_half] = coverage_left_right(axial);
                EXPECT_GT(left, right_half + 30);  // the right ear, on the viewer's left
            }
            for (std::size_t s = 1; s < series.size(); ++s) {
                SCOPED_TRACE(planes[s].name);
                const double error = rms(render(series[s], request), axial);
                EXPECT_LT(error, 0.005);
                volume::Volume as_stored = series[s];
                as_stored.axes = series[0].axes;  // the axial series' orientation
                const double ignored = rms(render(as_stored, request), axial);
                EXPECT_GT(ignored, 0.05);
                EXPECT_GT(ignored, 2.0 * error);
            }
        }
    }
}

// The CPU reference (shadow rays) agrees across storages too.
TEST(OrientationReferenceTest, CpuReferenceCastsTheSameShadowsOnEveryStorage) {
    const auto stored = storages();
    const auto request =
            head_request(scene::Mode::reference, scene::orbit_camera(35.0, 25.0, 2.6), 32);
    auto ras = reference::render_cpu(stored[0].volume, request);
    ASSERT_TRUE(ras.ok()) << ras.error().to_string();
    for (std::size_t s = 1; s < stored.size(); ++s) {
        SCOPED_TRACE(stored[s].name);
        auto image = reference::render_cpu(stored[s].volume, request);
        ASSERT_TRUE(image.ok());
        const double error = rms(*image, *ras);
        EXPECT_LT(error, stored[s].tolerance);
        volume::Volume as_stored = stored[s].volume;
        as_stored.axes = glm::dmat3(1.0);
        auto ignored = reference::render_cpu(as_stored, request);
        ASSERT_TRUE(ignored.ok());
        EXPECT_GT(rms(*ignored, *ras), 0.05);
        EXPECT_GT(rms(*ignored, *ras), 2.0 * error);
    }
}

}  // namespace
}  // namespace penumbra::render
