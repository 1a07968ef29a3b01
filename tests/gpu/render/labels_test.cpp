// Label maps drawn inside the volume: looked up by the nearest voxel of their own grid (so ids
// never mix, and a map on another grid or stored mirror-handed lands on the same anatomy), a hidden
// label transparent to the light as to the camera, and every mode against the CPU reference.

#include "receiver_scene.hpp"
#include "synthetic_volumes.hpp"

#include <penumbra/imageio/compare.hpp>
#include <penumbra/reference/cpu_renderer.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/box.hpp>
#include <penumbra/volume/label_map.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <utility>

namespace penumbra::render {
namespace {

using test::brightest_on_slab;
using test::receiver_red;
using test::receiver_scene;

// A label map of `dims` voxels whose ids `id_at` gives, on the grid the other arguments place.
std::shared_ptr<const volume::LabelMap> label_map(
        glm::uvec3 dims, glm::dvec3 spacing, glm::dvec3 origin, const glm::dmat3& axes,
        const std::function<std::uint8_t(unsigned, unsigned, unsigned)>& id_at) {
    std::vector<std::byte> ids;
    for (unsigned z = 0; z < dims.z; ++z) {
        for (unsigned y = 0; y < dims.y; ++y) {
            for (unsigned x = 0; x < dims.x; ++x) {
                ids.push_back(static_cast<std::byte>(id_at(x, y, z)));
            }
        }
    }
    auto stored = volume::make_volume("labels", dims, spacing, volume::VoxelType::uint8, ids);
    EXPECT_TRUE(stored.ok());
    stored->axes = axes;
    stored->origin = origin;
    auto map = volume::make_label_map(*stored, {});
    EXPECT_TRUE(map.ok()) << map.error().to_string();
    return std::make_shared<const volume::LabelMap>(std::move(map.value()));
}

class LabelsTest : public ::testing::Test {
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

    void use_labels(std::shared_ptr<const volume::LabelMap> labels) {
        labels_ = std::move(labels);
        const auto status = renderer_->set_labels(labels_);
        ASSERT_TRUE(status.ok()) << status.error().to_string();
    }

    Frame render(const scene::FrameRequest& request) {
        auto frame = renderer_->render(request);
        EXPECT_TRUE(frame.ok()) << frame.error().to_string();
        return frame.ok() ? std::move(frame.value()) : Frame{};
    }

    std::unique_ptr<Renderer> renderer_;
    std::shared_ptr<const volume::Volume> volume_;
    std::shared_ptr<const volume::LabelMap> labels_;
};

// The scene of cut_test: a receiver column (x in [n/8, 3n/8)) lit along -x, half of it behind a
// slab (x in [3n/4, 7n/8), y < n/2), seen from +z. The labels: the receiver 3, the slab 9 and the
// voxels around it, as a segmentation covers a structure: a sample takes the label of its nearest
// voxel, but its value blends the voxels around it, so the slab's values reach half a voxel into
// its neighbours, which must be hidden with it.
constexpr unsigned scene_side = 32;
constexpr std::int64_t receiver_id = 3;
constexpr std::int64_t slab_id = 9;

std::uint8_t scene_label(unsigned x, unsigned y, unsigned) {
    constexpr unsigned n = scene_side;
    if (x >= n / 8 && x < 3 * n / 8) {
        return receiver_id;
    }
    if (x + 1 >= 3 * n / 4 && x < 7 * n / 8 + 1 && y < n / 2 + 1) {
        return slab_id;
    }
    return 0;
}

void hide(scene::Labels& labels, std::int64_t id) {
    for (scene::LabelStyle& style : labels.styles) {
        if (style.id == id) {
            style.visible = false;
        }
    }
}

struct LabelCase {
    scene::Mode mode;
    scene::LightBufferBuilder builder;
};

class HiddenLabelShadowTest : public LabelsTest, public ::testing::WithParamInterface<LabelCase> {};

TEST_P(HiddenLabelShadowTest, AHiddenLabelNeitherShowsNorCastsAShadow) {
    use(test::shadow_scene(scene_side));
    use_labels(label_map(glm::uvec3(scene_side), glm::dvec3(1.0), glm::dvec3(0.0), glm::dmat3(1.0),
                         scene_label));
    scene::FrameRequest request = receiver_scene(GetParam().mode);
    request.settings.light_buffer.builder = GetParam().builder;
    request.labels = label_styles(*labels_);
    request.labels.blend = 0.0;  // the scan's colours: the shadow is measured on them
    const Frame shown = render(request);
    const double expected =
            std::exp(-0.03 / request.settings.opacity_unit_distance * 4.0 / scene_side);
    EXPECT_NEAR(receiver_red(shown, 40, 47) / receiver_red(shown, 17, 24), expected, 0.01);
    ASSERT_GT(brightest_on_slab(shown), 10.0);

    const std::uint64_t builds = renderer_->light_buffer_builds();
    hide(request.labels, slab_id);
    const Frame hidden = render(request);
    const double lit = receiver_red(hidden, 17, 24);
    ASSERT_GT(lit, 40.0);
    EXPECT_NEAR(receiver_red(hidden, 40, 47) / lit, 1.0, 0.01) << "the hidden slab's shadow";
    EXPECT_EQ(brightest_on_slab(hidden), 0.0);
    EXPECT_NEAR(lit, receiver_red(shown, 17, 24), 1.0);
    if (scene::uses_light_buffer(GetParam().mode)) {
        // A visibility change rebuilds the light buffer once; a camera move or a colour never.
        EXPECT_EQ(renderer_->light_buffer_builds(), builds + 1);
        request.camera.eye = {0.3, 0.2, 3.0};
        request.labels.styles[0].color = {0.2, 0.9, 0.1};
        request.labels.blend = 0.5;
        render(request);
        EXPECT_EQ(renderer_->light_buffer_builds(), builds + 1);
    }
}

INSTANTIATE_TEST_SUITE_P(
        Modes, HiddenLabelShadowTest,
        ::testing::Values(LabelCase{scene::Mode::reference, scene::LightBufferBuilder::multi_slice},
                          LabelCase{scene::Mode::sbrc, scene::LightBufferBuilder::multi_slice},
                          LabelCase{scene::Mode::sbrc, scene::LightBufferBuilder::per_slice},
                          LabelCase{scene::Mode::half_angle,
                                    scene::LightBufferBuilder::multi_slice}),
        [](const auto& param_info) {
            return std::string(scene::to_string(param_info.param.mode)) + "_" +
                   std::string(scene::to_string(param_info.param.builder));
        });

// An opaque volume under a checkerboard of two labels, coloured pure red and pure blue with the
// label's colour alone: every pixel is the one label of the first sample, never a mix.
TEST_F(LabelsTest, LabelsNeverMixAtTheirBoundaries) {
    use(test::constant_volume(glm::uvec3(32), 1.0f));
    // Another grid: 5 mm voxels offset by a third of one, over the 32 mm of the scan.
    use_labels(label_map(glm::uvec3(8), glm::dvec3(5.0), glm::dvec3(-1.7), glm::dmat3(1.0),
                         [](unsigned x, unsigned y, unsigned z) -> std::uint8_t {
                             return (x + y + z) % 2 == 0 ? 1 : 2;
                         }));
    scene::FrameRequest request;
    request.camera.eye = {1.2, 1.6, 2.2};
    request.settings.mode = scene::Mode::dvr;
    request.settings.width = 96;
    request.settings.height = 96;
    request.transfer_function = {"opaque", {{0.0, {1.0, 1.0, 1.0}}}, {{0.0, 1.0}, {1.0, 1.0}}};
    request.labels = label_styles(*labels_);
    request.labels.blend = 1.0;
    request.labels.styles[0].color = {1.0, 0.0, 0.0};
    request.labels.styles[1].color = {0.0, 0.0, 1.0};
    const Frame frame = render(request);
    int red = 0;
    int blue = 0;
    int mixed = 0;
    for (int y = 0; y < frame.image.height; ++y) {
        for (int x = 0; x < frame.image.width; ++x) {
            const std::uint8_t* p = frame.image.pixel(x, y);
            if (p[1] != 0) {
                ++mixed;
            } else if (p[0] > 0 && p[2] == 0) {
                ++red;
            } else if (p[2] > 0 && p[0] == 0) {
                ++blue;
            } else if (p[0] != 0 || p[2] != 0) {
                ++mixed;
            }
        }
    }
    EXPECT_GT(red, 500);
    EXPECT_GT(blue, 500);
    EXPECT_EQ(mixed, 0);
}

// The same labels on the scan's grid, stored mirror-handed (x reversed, as FSL writes LAS), and on
// a grid twice as fine (each voxel split in eight, the grid's outer faces where the scan's are):
// drawn on the same anatomy, the three frames are the same.
TEST_F(LabelsTest, ALabelMapOnAnotherGridOrMirroredLandsOnTheSameAnatomy) {
    constexpr unsigned n = scene_side;
    use(test::shadow_scene(n));
    scene::FrameRequest request = receiver_scene(scene::Mode::phong);
    request.camera.eye = {1.5, 1.0, 2.5};
    const auto id_at = [](unsigned x, unsigned y, unsigned z) -> std::uint8_t {
        return scene_label(x, y, z) != 0 ? static_cast<std::uint8_t>(1 + (x + 2 * y + z) / 5 % 4)
                                         : 0;
    };
    const auto draw = [&](std::shared_ptr<const volume::LabelMap> labels) {
        use_labels(std::move(labels));
        request.labels = label_styles(*labels_);
        request.labels.blend = 0.8;
        hide(request.labels, 2);
        return render(request);
    };
    const Frame same_grid = draw(
            label_map(glm::uvec3(n), glm::dvec3(1.0), glm::dvec3(0.0), glm::dmat3(1.0), id_at));
    glm::dmat3 mirrored(1.0);
    mirrored[0] = {-1.0, 0.0, 0.0};
    const Frame mirror = draw(
            label_map(glm::uvec3(n), glm::dvec3(1.0), glm::dvec3(n - 1.0, 0.0, 0.0), mirrored,
                      [&](unsigned x, unsigned y, unsigned z) { return id_at(n - 1 - x, y, z); }));
    const Frame fine = draw(label_map(
            glm::uvec3(2 * n), glm::dvec3(0.5), glm::dvec3(-0.25), glm::dmat3(1.0),
            [&](unsigned x, unsigned y, unsigned z) { return id_at(x / 2, y / 2, z / 2); }));
    for (const Frame* other : {&mirror, &fine}) {
        auto difference = imageio::compare_images(base::to_rgba_f(same_grid.image),
                                                  base::to_rgba_f(other->image));
        ASSERT_TRUE(difference.ok());
        EXPECT_GT(difference->psnr, 60.0) << (other == &mirror ? "mirrored" : "finer grid");
    }
}

// The AAL atlas inside the ch2 head (mricron-data, on ch2's grid), and the same atlas stored
// left-right reversed (LAS, as FSL writes Harvard-Oxford): the same regions land on the same
// anatomy, a few of them hidden.
TEST_F(LabelsTest, TheAalAtlasStoredMirrorHandedDrawsTheSameHead) {
    const std::filesystem::path templates = "/usr/share/mricron/templates";
    auto ch2 = volume::load_volume(templates / "ch2bet.nii.gz");
    auto aal = volume::load_label_map(templates / "aal.nii.gz");
    ASSERT_TRUE(ch2.ok() && aal.ok());
    use(*ch2);
    volume::LabelMap mirrored = *aal;
    volume::Volume& indices = mirrored.indices;
    const glm::uvec3 n = indices.dims;
    for (unsigned z = 0; z < n.z; ++z) {
        for (unsigned y = 0; y < n.y; ++y) {
            const std::size_t row = (static_cast<std::size_t>(z) * n.y + y) * n.x;
            for (unsigned x = 0; x < n.x; ++x) {
                indices.data[row + x] = aal->indices.data[row + n.x - 1 - x];
            }
        }
    }
    indices.origin += indices.axes[0] * (indices.spacing.x * (n.x - 1.0));
    indices.axes[0] = -indices.axes[0];
    scene::FrameRequest request;
    request.settings.mode = scene::Mode::phong;
    request.settings.width = 96;
    request.settings.height = 96;
    request.camera.eye = {-2.2, 0.8, 1.0};  // from the left, where the two differ if at all
    request.transfer_function = {
            "brain", {{0.0, {1.0, 1.0, 1.0}}}, {{0.0, 0.0}, {0.2, 0.0}, {0.3, 0.5}, {1.0, 0.8}}};
    const auto draw = [&](volume::LabelMap labels) {
        use_labels(std::make_shared<const volume::LabelMap>(std::move(labels)));
        request.labels = label_styles(*labels_);
        request.labels.blend = 0.9;
        for (const std::int64_t id : {1, 19, 43, 59}) {  // Precentral_L, SMA_L, Calcarine_L, ...
            hide(request.labels, id);
        }
        return render(request);
    };
    const Frame atlas = draw(*aal);
    const Frame reversed = draw(std::move(mirrored));
    auto difference =
            imageio::compare_images(base::to_rgba_f(atlas.image), base::to_rgba_f(reversed.image));
    ASSERT_TRUE(difference.ok());
    EXPECT_GT(difference->psnr, 55.0);
    // And the labels do show: without them the head is another image.
    request.labels = {};
    const Frame plain = render(request);
    auto unlabelled =
            imageio::compare_images(base::to_rgba_f(atlas.image), base::to_rgba_f(plain.image));
    ASSERT_TRUE(unlabelled.ok());
    EXPECT_LT(unlabelled->psnr, 30.0);
}

// Every mode with labels, one of them hidden, against the CPU reference drawing the same labels
// (the shadow modes against its shadow rays), as close as each mode is without labels.
class LabelsAgainstReferenceTest : public LabelsTest,
                                   public ::testing::WithParamInterface<LabelCase> {};

TEST_P(LabelsAgainstReferenceTest, EveryModeDrawsTheLabelsAsTheReference) {
    use(test::shadow_scene(scene_side));
    use_labels(label_map(glm::uvec3(scene_side), glm::dvec3(1.0), glm::dvec3(0.0), glm::dmat3(1.0),
                         scene_label));
    const scene::Mode mode = GetParam().mode;
    scene::FrameRequest request = receiver_scene(mode);
    request.camera.eye = {1.2, 0.8, 2.6};
    request.light.ambient = 0.2;
    request.settings.light_buffer.builder = GetParam().builder;
    const auto psnr = [&](const scene::FrameRequest& r) {
        const Frame frame = render(r);
        scene::FrameRequest truth = r;
        if (mode != scene::Mode::dvr && mode != scene::Mode::phong) {
            truth.settings.mode = scene::Mode::reference;
        }
        auto expected = reference::render_cpu(*volume_, truth, labels_.get());
        EXPECT_TRUE(expected.ok()) << expected.error().to_string();
        auto difference = imageio::compare_images(base::to_rgba_f(frame.image), *expected);
        return difference.ok() ? difference->psnr : 0.0;
    };
    const double unlabelled = psnr(request);
    request.labels = label_styles(*labels_);
    request.labels.styles[0].color = {0.9, 0.3, 0.1};
    request.labels.styles[1].color = {0.1, 0.4, 0.9};
    request.labels.styles[1].opacity = 0.7;
    hide(request.labels, slab_id);
    const double hidden = psnr(request);
    hide(request.labels, receiver_id);
    request.labels.styles[1].visible = true;
    const double labelled = psnr(request);
    // Half-angle slicing takes one point per slice: the receiver's hidden voxels leave a sheet half
    // a voxel thin where their values reach into the background's (labels.glsl), which its slices
    // sample otherwise than the reference's rays (39 dB where the ray-cast modes stay within 2).
    const bool sliced = mode == scene::Mode::half_angle;
    EXPECT_GT(hidden, unlabelled - 3.0) << "slab hidden";
    EXPECT_GT(labelled, unlabelled - (sliced ? 8.0 : 3.0)) << "receiver hidden, slab at 0.7";
    EXPECT_GT(std::min(hidden, labelled), sliced ? 36.0 : 50.0);
    std::printf("%s: %.1f dB without labels, %.1f and %.1f with\n", scene::to_string(mode),
                unlabelled, hidden, labelled);
}

INSTANTIATE_TEST_SUITE_P(
        Modes, LabelsAgainstReferenceTest,
        ::testing::Values(
                LabelCase{scene::Mode::dvr, scene::LightBufferBuilder::multi_slice},
                LabelCase{scene::Mode::phong, scene::LightBufferBuilder::multi_slice},
                LabelCase{scene::Mode::reference, scene::LightBufferBuilder::multi_slice},
                LabelCase{scene::Mode::sbrc, scene::LightBufferBuilder::multi_slice},
                LabelCase{scene::Mode::sbrc, scene::LightBufferBuilder::per_slice},
                LabelCase{scene::Mode::sbrc_shell, scene::LightBufferBuilder::multi_slice},
                LabelCase{scene::Mode::sbrc_cone, scene::LightBufferBuilder::multi_slice},
                LabelCase{scene::Mode::half_angle, scene::LightBufferBuilder::multi_slice}),
        [](const auto& param_info) {
            return std::string(scene::to_string(param_info.param.mode)) + "_" +
                   std::string(scene::to_string(param_info.param.builder));
        });

TEST_F(LabelsTest, StylesThatAreNotTheMapsOrAMapOutsideTheScanAreRefused) {
    use(test::shadow_scene(scene_side));
    scene::FrameRequest request = receiver_scene(scene::Mode::dvr);
    request.labels.styles = {{.id = 3}};
    auto frame = renderer_->render(request);
    ASSERT_FALSE(frame.ok());
    EXPECT_EQ(frame.error().code, base::ErrorCode::invalid_frame);  // no label map set

    auto labels = label_map(glm::uvec3(scene_side), glm::dvec3(1.0), glm::dvec3(0.0),
                            glm::dmat3(1.0), scene_label);
    use_labels(labels);
    frame = renderer_->render(request);  // one style for two labels
    ASSERT_FALSE(frame.ok());
    EXPECT_NE(frame.error().message.find("holds 2"), std::string::npos) << frame.error().message;
    request.labels = label_styles(*labels_);
    std::swap(request.labels.styles[0], request.labels.styles[1]);
    frame = renderer_->render(request);
    ASSERT_FALSE(frame.ok());
    EXPECT_NE(frame.error().message.find("in its order"), std::string::npos);
    request.labels.styles[0].opacity = 1.5;
    frame = renderer_->render(request);
    ASSERT_FALSE(frame.ok());
    EXPECT_EQ(frame.error().code, base::ErrorCode::invalid_value);

    auto far_away = label_map(glm::uvec3(4), glm::dvec3(1.0), glm::dvec3(500.0), glm::dmat3(1.0),
                              [](unsigned, unsigned, unsigned) -> std::uint8_t { return 1; });
    const auto status = renderer_->set_labels(far_away);
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.error().code, base::ErrorCode::no_overlap);
    // The label map set before still draws.
    request.labels = label_styles(*labels_);
    EXPECT_TRUE(renderer_->render(request).ok());
}

// Two sessions drawing two label maps on one renderer: both stay on the GPU, and switching back
// draws the first as before; null draws none.
TEST_F(LabelsTest, LabelMapsStayOnTheGpuBetweenSwitches) {
    use(test::shadow_scene(scene_side));
    const std::size_t scan_only = renderer_->gpu_bytes_held();
    auto first = label_map(glm::uvec3(scene_side), glm::dvec3(1.0), glm::dvec3(0.0),
                           glm::dmat3(1.0), scene_label);
    auto second = label_map(glm::uvec3(scene_side), glm::dvec3(1.0), glm::dvec3(0.0),
                            glm::dmat3(1.0), [](unsigned x, unsigned, unsigned) -> std::uint8_t {
                                return x < scene_side / 2 ? 5 : 6;
                            });
    scene::FrameRequest request = receiver_scene(scene::Mode::sbrc);
    use_labels(first);
    request.labels = label_styles(*first);
    hide(request.labels, slab_id);
    const Frame before = render(request);
    use_labels(second);
    scene::FrameRequest other = request;
    other.labels = label_styles(*second);
    render(other);
    EXPECT_EQ(renderer_->gpu_bytes_held() - scan_only >= 2 * first->indices.data.size(), true);
    use_labels(first);
    const Frame again = render(request);
    auto difference =
            imageio::compare_images(base::to_rgba_f(before.image), base::to_rgba_f(again.image));
    ASSERT_TRUE(difference.ok());
    EXPECT_EQ(difference->max_error, 0.0);
    ASSERT_TRUE(renderer_->set_labels(nullptr).ok());
    auto refused = renderer_->render(request);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::invalid_frame);
}

// The label map alone as surfaces (volume::label_surfaces, drawn with its transfer function): a
// ball of label 1 and a box of label 2, the box hidden. The GPU draws what the CPU reference draws
// from the same indicator and labels; the hidden box is no surface; and the ball's shading is
// smooth where its voxels make steps: the ids drawn as a scan with the same threshold show the
// staircase, many times rougher.
TEST_F(LabelsTest, LabelsAloneAreSmoothSurfacesAsTheReferenceDrawsThem) {
    constexpr unsigned side = 40;
    const auto map = label_map(glm::uvec3(side), glm::dvec3(1.0), glm::dvec3(0.0), glm::dmat3(1.0),
                               [](unsigned x, unsigned y, unsigned z) -> std::uint8_t {
                                   const glm::dvec3 p(x, y, z);
                                   if (glm::length(p - glm::dvec3(20.0, 20.0, 20.0)) < 11.0) {
                                       return 1;
                                   }
                                   return x >= 33 && y >= 33 && z >= 30 ? 2 : 0;
                               });
    auto surfaces = volume::label_surfaces(*map, {true, false});
    ASSERT_TRUE(surfaces.ok()) << surfaces.error().to_string();
    use(surfaces->indicator);
    use_labels(std::make_shared<const volume::LabelMap>(surfaces->labels));
    scene::FrameRequest request;
    request.settings.width = 96;
    request.settings.height = 96;
    request.settings.mode = scene::Mode::phong;
    request.camera.eye = {1.5, 1.1, 2.4};
    request.labels = label_styles(*labels_);
    request.labels.alone = true;
    request = scene::labels_alone_request(std::move(request));
    request.labels.styles[0].color = {0.9, 0.5, 0.2};
    hide(request.labels, 2);
    const Frame frame = render(request);
    auto expected = reference::render_cpu(*volume_, request, labels_.get());
    ASSERT_TRUE(expected.ok()) << expected.error().to_string();
    auto difference = imageio::compare_images(base::to_rgba_f(frame.image), *expected);
    ASSERT_TRUE(difference.ok());
    EXPECT_GT(difference->psnr, 45.0);

    // Only the ball's colour: no pixel of the hidden box, no white of the transfer function where
    // a sample falls outside the ball's voxels.
    int ball = 0;
    int other = 0;
    for (int y = 0; y < frame.image.height; ++y) {
        for (int x = 0; x < frame.image.width; ++x) {
            const std::uint8_t* p = frame.image.pixel(x, y);
            const int r = p[0];
            const int g = p[1];
            const int b = p[2];
            if (r + g + b < 30) {
                continue;  // the background, or the ball's shadowed side
            }
            const bool orange = r > g && g > b;
            (orange ? ball : other) += 1;
        }
    }
    EXPECT_GT(ball, 500);
    EXPECT_EQ(other, 0);

    // Roughness: the mean absolute Laplacian of the luminance where both images show the ball.
    const auto roughness = [](const base::ImageRgba8& image, const base::ImageRgba8& mask) {
        const auto luminance = [&](const base::ImageRgba8& im, int x, int y) {
            const std::uint8_t* p = im.pixel(x, y);
            return 0.3 * p[0] + 0.59 * p[1] + 0.11 * p[2];
        };
        double sum = 0.0;
        int count = 0;
        for (int y = 2; y < image.height - 2; ++y) {
            for (int x = 2; x < image.width - 2; ++x) {
                bool inside = true;
                for (int d = -2; d <= 2 && inside; ++d) {
                    inside = luminance(mask, x + d, y) > 20.0 && luminance(mask, x, y + d) > 20.0;
                }
                if (!inside) {
                    continue;
                }
                sum += std::abs(4.0 * luminance(image, x, y) - luminance(image, x - 1, y) -
                                luminance(image, x + 1, y) - luminance(image, x, y - 1) -
                                luminance(image, x, y + 1));
                ++count;
            }
        }
        return count > 0 ? sum / count : 0.0;
    };
    const double smooth = roughness(frame.image, frame.image);
    // The ids as a scan, the ball alone, thresholded half way between 0 and its id: its voxels.
    auto ids = volume::make_volume("ids", glm::uvec3(side), glm::dvec3(1.0),
                                   volume::VoxelType::uint8, map->indices.data);
    ASSERT_TRUE(ids.ok());
    use(*ids);
    scene::FrameRequest staircase = request;
    staircase.labels = {};
    staircase.transfer_function.colors = {{0.0, {0.9, 0.5, 0.2}}, {1.0, {0.9, 0.5, 0.2}}};
    staircase.transfer_function.opacities = {{0.0, 0.0}, {0.24, 0.0}, {0.26, 1.0},
                                             {0.5, 1.0}, {0.51, 0.0}, {1.0, 0.0}};
    const Frame steps = render(staircase);
    const double stepped = roughness(steps.image, frame.image);
    std::printf("roughness: %.2f as surfaces, %.2f as voxels\n", smooth, stepped);
    EXPECT_LT(smooth * 4.0, stepped);
}

}  // namespace
}  // namespace penumbra::render
