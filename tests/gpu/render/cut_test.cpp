// Cutting into the volume: a crop box and clip planes that every pass asks (optics::Region), with
// the tissue they remove casting no shadow (a virtual dissection) or still casting it (context
// shadows), checked against analytic transmittance, against the CPU reference and for the light
// buffer's reuse.

#include "receiver_scene.hpp"
#include "synthetic_volumes.hpp"

#include <penumbra/imageio/compare.hpp>
#include <penumbra/reference/cpu_renderer.hpp>
#include <penumbra/render/renderer.hpp>
#include <penumbra/scene/box.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>

namespace penumbra::render {
namespace {

using test::brightest_on_slab;
using test::receiver_red;
using test::receiver_scene;

// In the receiver scene (receiver_scene.hpp) a crop keeping x < 0.2 of the world removes the slab
// and nothing of the receiver.

class CutTest : public ::testing::Test {
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

    // A crop box in patient millimetres from its corners in world space (the volume's longest
    // side is 1): the tests think in world space, the protocol in patient space.
    [[nodiscard]] scene::Cut crop_world(glm::dvec3 low, glm::dvec3 high, bool casts_shadows) const {
        const scene::PatientPlacement placement = scene::patient_placement(
                volume_->origin, volume_->axes, volume_->spacing, glm::dvec3(volume_->dims));
        scene::Cut cut;
        cut.crop = {true, placement.to_patient(low), placement.to_patient(high)};
        cut.casts_shadows = casts_shadows;
        return cut;
    }

    // A clip plane in patient millimetres through a point of world space; the normal is the same
    // in both spaces, which differ by a move and a scale.
    [[nodiscard]] scene::ClipPlane plane_world(glm::dvec3 point, glm::dvec3 normal) const {
        const scene::PatientPlacement placement = scene::patient_placement(
                volume_->origin, volume_->axes, volume_->spacing, glm::dvec3(volume_->dims));
        return {true, placement.to_patient(point), normal};
    }

    std::unique_ptr<Renderer> renderer_;
    std::shared_ptr<const volume::Volume> volume_;
};

struct CutCase {
    scene::Mode mode;
    scene::LightBufferBuilder builder;
};

class CutShadowTest : public CutTest, public ::testing::WithParamInterface<CutCase> {};

TEST_P(CutShadowTest, CutTissueCastsNoShadowUnlessAsked) {
    constexpr unsigned n = 32;
    use(test::shadow_scene(n));
    scene::FrameRequest request = receiver_scene(GetParam().mode);
    request.settings.light_buffer.builder = GetParam().builder;
    const Frame whole = render(request);
    const double expected = std::exp(-0.03 / request.settings.opacity_unit_distance * 4.0 / n);
    const double whole_ratio = receiver_red(whole, 40, 47) / receiver_red(whole, 17, 24);
    EXPECT_NEAR(whole_ratio, expected, 0.01);
    ASSERT_GT(brightest_on_slab(whole), 10.0);  // the slab shows where it is not cut

    // Virtual dissection: the slab is gone for the light as for the camera.
    request.cut = crop_world(glm::dvec3(-1.0), glm::dvec3(0.2, 1.0, 1.0), false);
    const Frame dissected = render(request);
    const double lit = receiver_red(dissected, 17, 24);
    ASSERT_GT(lit, 40.0);
    EXPECT_NEAR(receiver_red(dissected, 40, 47) / lit, 1.0, 0.01);
    EXPECT_EQ(brightest_on_slab(dissected), 0.0);
    EXPECT_NEAR(lit, receiver_red(whole, 17, 24), 1.0);

    // Context shadows: the slab is not drawn, its shadow stays.
    request.cut.casts_shadows = true;
    const Frame context = render(request);
    EXPECT_NEAR(receiver_red(context, 40, 47) / receiver_red(context, 17, 24), expected, 0.01);
    EXPECT_EQ(brightest_on_slab(context), 0.0);

    // The same with a tilted plane (x <= 0.1 + 0.2 z kept: the slab goes, the receiver stays).
    request.cut = {};
    request.cut.planes[3] = plane_world({0.1, 0.0, 0.0}, {-1.0, 0.0, 0.2});
    const Frame planed = render(request);
    EXPECT_NEAR(receiver_red(planed, 40, 47) / receiver_red(planed, 17, 24), 1.0, 0.01);
    EXPECT_NEAR(receiver_red(planed, 17, 24), lit, 1.0);
    EXPECT_EQ(brightest_on_slab(planed), 0.0);
    request.cut.casts_shadows = true;
    const Frame planed_context = render(request);
    EXPECT_NEAR(receiver_red(planed_context, 40, 47) / receiver_red(planed_context, 17, 24),
                expected, 0.01);

    // A plane that holds the light's direction (z >= 0 kept, the light along -x): what it keeps
    // is shadowed by what it keeps alone, the slab's upper half, as before the cut.
    for (const bool casts_shadows : {false, true}) {
        request.cut = {};
        request.cut.planes[0] = plane_world({0.0, 0.0, 0.0}, {0.0, 0.0, 1.0});
        request.cut.casts_shadows = casts_shadows;
        const Frame halved = render(request);
        EXPECT_NEAR(receiver_red(halved, 40, 47) / receiver_red(halved, 17, 24), expected, 0.01)
                << (casts_shadows ? "context shadows" : "dissection");
    }
}

INSTANTIATE_TEST_SUITE_P(
        Modes, CutShadowTest,
        ::testing::Values(CutCase{scene::Mode::reference, scene::LightBufferBuilder::multi_slice},
                          CutCase{scene::Mode::sbrc, scene::LightBufferBuilder::multi_slice},
                          CutCase{scene::Mode::sbrc, scene::LightBufferBuilder::per_slice},
                          CutCase{scene::Mode::half_angle, scene::LightBufferBuilder::multi_slice}),
        [](const auto& param_info) {
            return std::string(scene::to_string(param_info.param.mode)) + "_" +
                   std::string(scene::to_string(param_info.param.builder));
        });

// The modes with no shadow (dvr, phong) or a shadow of their own kind (shell and cone samples),
// whose shadow does not equal the slab's analytic transmittance: with the slab cut away it is not
// drawn; with dissection the receiver behind it is lit like its free part (or, with no shadow,
// like the uncut frame); with context shadows the receiver is exactly as in the uncut frame.
class CutEveryModeTest : public CutTest, public ::testing::WithParamInterface<scene::Mode> {};

TEST_P(CutEveryModeTest, TheCutSlabIsNotDrawnAndShadowsOnlyWhenAsked) {
    use(test::shadow_scene(32));
    scene::FrameRequest request = receiver_scene(GetParam());
    request.settings.light_buffer.resolution = 128;
    const bool shadows = GetParam() != scene::Mode::dvr && GetParam() != scene::Mode::phong;
    const Frame whole = render(request);
    const double whole_free = receiver_red(whole, 17, 24);
    const double whole_behind = receiver_red(whole, 40, 47);
    ASSERT_GT(whole_free, 40.0);
    ASSERT_GT(brightest_on_slab(whole), 10.0);
    if (shadows) {
        EXPECT_LT(whole_behind / whole_free, 0.8) << "the slab shadows the receiver";
    } else {
        EXPECT_NEAR(whole_behind / whole_free, 1.0, 0.01);
    }

    for (const bool casts_shadows : {false, true}) {
        for (const bool planed : {false, true}) {
            SCOPED_TRACE(std::string(casts_shadows ? "context shadows" : "dissection") +
                         (planed ? ", plane" : ", crop"));
            if (planed) {
                request.cut = {};
                request.cut.planes[4] = plane_world({0.1, 0.0, 0.0}, {-1.0, 0.0, 0.2});
                request.cut.casts_shadows = casts_shadows;
            } else {
                request.cut =
                        crop_world(glm::dvec3(-1.0), glm::dvec3(0.2, 1.0, 1.0), casts_shadows);
            }
            const Frame cut = render(request);
            EXPECT_EQ(brightest_on_slab(cut), 0.0);
            EXPECT_NEAR(receiver_red(cut, 17, 24), whole_free, 1.0);
            if (casts_shadows || !shadows) {
                EXPECT_NEAR(receiver_red(cut, 40, 47), whole_behind, 1.0);
            } else {
                EXPECT_NEAR(receiver_red(cut, 40, 47) / receiver_red(cut, 17, 24), 1.0, 0.02);
            }
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Modes, CutEveryModeTest,
                         ::testing::Values(scene::Mode::dvr, scene::Mode::phong,
                                           scene::Mode::sbrc_shell, scene::Mode::sbrc_cone),
                         [](const auto& param_info) {
                             return std::string(scene::to_string(param_info.param));
                         });

// The GPU's region against the CPU reference's, from outside the volume and from inside it (the
// eye in the kept part and in the part cut away), with a point light in the cut-away part.
TEST_F(CutTest, GpuMatchesTheCpuReferenceWithACrop) {
    const volume::Volume volume = test::radial_volume(32);
    use(volume);

    struct Eye {
        const char* what;
        scene::Camera camera;
    };

    const Eye eyes[] = {
            {"outside", scene::orbit_camera(35.0, 20.0, 2.4)},
            {"inside the kept part", {{-0.1, -0.15, 0.1}, {0.2, 0.3, -0.1}, {0.0, 0.0, 1.0}, 60.0}},
            {"inside the cut-away part",
             {{0.3, 0.3, 0.2}, {-0.2, -0.1, 0.0}, {0.0, 0.0, 1.0}, 60.0}},
            {"inside the crop, cut away by the plane",
             {{0.0, 0.1, 0.42}, {-0.1, -0.2, 0.0}, {0.0, 0.0, 1.0}, 60.0}},
    };
    for (const Eye& eye : eyes) {
        for (const bool casts_shadows : {false, true}) {
            SCOPED_TRACE(std::string(eye.what) + (casts_shadows ? ", context shadows" : ""));
            scene::FrameRequest request;
            request.camera = eye.camera;
            request.light.type = scene::LightType::point;
            request.light.position = {0.4, 0.3, 0.35};
            request.light.ambient = 0.1;
            request.settings.mode = scene::Mode::reference;
            request.settings.phong = true;
            request.settings.width = 48;
            request.settings.height = 48;
            request.settings.sample_distance = 1.0 / 96.0;
            request.transfer_function = {"soft",
                                         {{0.0, {1.0, 0.9, 0.8}}, {1.0, {1.0, 1.0, 1.0}}},
                                         {{0.0, 0.0}, {0.3, 0.0}, {1.0, 0.15}}};
            request.cut = crop_world({-0.6, -0.6, -0.12}, {0.1, 0.15, 0.6}, casts_shadows);
            // With a tilted plane as well, which also removes the last eye, inside the crop.
            for (const bool planed : {false, true}) {
                SCOPED_TRACE(planed ? "crop and plane" : "crop");
                if (planed) {
                    request.cut.planes[5] = plane_world({0.0, 0.0, 0.3}, {0.2, -0.5, -0.4});
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
    }
}

// Planes through the eye: one along the view keeps the half of the image its normal points to,
// as the CPU reference draws it; one across the view keeps all that lies before the eye (it cuts
// nothing and is left out) or, turned back, nothing at all.
TEST_F(CutTest, APlaneThroughTheEyeCutsAsTheReferenceDoes) {
    const volume::Volume volume = test::radial_volume(24);
    use(volume);
    scene::FrameRequest request;
    request.camera = scene::orbit_camera(30.0, 15.0, 2.2);
    request.light.direction = {0.3, -0.5, 0.8};
    request.settings.mode = scene::Mode::reference;
    request.settings.phong = true;
    request.settings.width = request.settings.height = 40;
    request.settings.sample_distance = 1.0 / 96.0;
    request.settings.background = {0.2, 0.4, 0.6};
    request.transfer_function = {
            "soft", {{0.0, {1.0, 0.9, 0.8}}}, {{0.0, 0.0}, {0.3, 0.0}, {1.0, 0.2}}};
    const glm::dvec3 eye = request.camera.eye;
    const glm::dvec3 forward = glm::normalize(request.camera.target - eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, request.camera.up));

    request.cut.planes[0] = plane_world(eye, right);
    const Frame along = render(request);
    auto expected = reference::render_cpu(volume, request);
    ASSERT_TRUE(expected.ok()) << expected.error().to_string();
    auto difference = imageio::compare_images(base::to_rgba_f(along.image), *expected);
    ASSERT_TRUE(difference.ok());
    EXPECT_LE(difference->max_error, 3.0 / 255.0);
    // The left half is background, the right half shows the ball.
    EXPECT_NEAR(along.image.pixel(12, 20)[2], 153, 1);
    EXPECT_NE(along.image.pixel(23, 20)[2], 153);

    request.cut.planes[0] = plane_world(eye, forward);
    const Frame before = render(request);
    request.cut = {};
    const Frame uncut = render(request);
    auto same =
            imageio::compare_images(base::to_rgba_f(before.image), base::to_rgba_f(uncut.image));
    ASSERT_TRUE(same.ok());
    EXPECT_EQ(same->max_error, 0.0);

    request.cut.planes[0] = plane_world(eye, -forward);
    const Frame behind = render(request);
    for (int y = 0; y < 40; ++y) {
        for (int x = 0; x < 40; ++x) {
            ASSERT_NEAR(behind.image.pixel(x, y)[2], 153, 1) << x << "," << y;
        }
    }
}

// A ball cut in half and seen face on, lit from the eye: within the cut face the material's own
// gradient lies along the face (it is radial), which would shade it dark away from the centre;
// with what the cut removed taken as empty the face is shaded as facing out of the cut, evenly.
TEST_F(CutTest, ACutFaceIsShadedAsASurfaceFacingOutOfTheCut) {
    use(test::radial_volume(32));
    for (const scene::Mode mode : {scene::Mode::phong, scene::Mode::half_angle}) {
        SCOPED_TRACE(scene::to_string(mode));
        scene::FrameRequest request;
        request.camera.eye = {-2.5, 0.0, 0.0};
        request.camera.target = {0.0, 0.0, 0.0};
        request.camera.up = {0.0, 0.0, 1.0};
        request.light.direction = {-1.0, 0.0, 0.0};
        request.light.ambient = 0.0;
        request.settings.mode = mode;
        request.settings.phong = true;
        request.settings.shading.specular = 0.0;
        request.settings.width = request.settings.height = 64;
        request.settings.sample_distance = 1.0 / 128.0;
        request.settings.light_buffer.slices = 128;
        request.transfer_function = {"ball",
                                     {{0.0, {1.0, 1.0, 1.0}}},
                                     {{0.0, 0.0}, {0.3, 0.0}, {0.35, 1.0}, {1.0, 1.0}}};
        request.cut = crop_world({0.0, -1.0, -1.0}, glm::dvec3(1.0), false);
        const Frame frame = render(request);
        // The face is a disc of radius 0.35 (about 16 pixels) around the centre; its ring at 6 to
        // 11 pixels against its middle.
        double ring = 0.0;
        int ring_count = 0;
        double middle = 0.0;
        int middle_count = 0;
        for (int y = 0; y < 64; ++y) {
            for (int x = 0; x < 64; ++x) {
                const double r = std::hypot(x + 0.5 - 32.0, y + 0.5 - 32.0);
                const double red = frame.image.pixel(x, y)[0];
                if (r >= 6.0 && r <= 11.0) {
                    ring += red;
                    ++ring_count;
                } else if (r <= 3.0) {
                    middle += red;
                    ++middle_count;
                }
            }
        }
        ring /= ring_count;
        middle /= middle_count;
        ASSERT_GT(middle, 150.0);
        EXPECT_GT(ring, 0.95 * middle) << "ring " << ring << ", middle " << middle;
    }
}

// A cut face turned to the light, seen face on: with dissection nothing lies between it and the
// light, so the local lookup's stretch toward the light, which starts in what was cut away, must
// count none of it (the samples within a stretch of a face test it; deeper ones need not), and
// the slab the face crosses dims the light by the part of it that is kept, not by whether a
// point happens to fall in it (that lit the face 20/255 brighter than the reference). Each
// light-buffer mode lights the face as the reference's shadow rays do.
TEST_F(CutTest, ACutFaceTurnedToTheLightIsLitFully) {
    use(test::radial_volume(32));
    const auto face_red = [&](scene::Mode mode, const auto& adjust) {
        scene::FrameRequest request;
        request.camera.eye = {2.5, 0.0, 0.0};
        request.camera.target = {0.0, 0.0, 0.0};
        request.camera.up = {0.0, 0.0, 1.0};
        request.light.direction = {1.0, 0.0, 0.0};
        request.light.ambient = 0.0;
        request.settings.mode = mode;
        request.settings.width = request.settings.height = 48;
        request.settings.sample_distance = 1.0 / 128.0;
        request.settings.light_buffer.slices = 64;
        request.settings.light_buffer.resolution = 64;
        request.transfer_function = {"ball",
                                     {{0.0, {1.0, 1.0, 1.0}}},
                                     {{0.0, 0.0}, {0.3, 0.0}, {0.35, 0.3}, {1.0, 0.3}}};
        // Keeps x <= 0.01: the face lies inside a slab, not on a slice plane.
        request.cut = crop_world(glm::dvec3(-1.0), {0.01, 1.0, 1.0}, false);
        adjust(request);
        const Frame frame = render(request);
        double sum = 0.0;
        for (int y = 20; y < 28; ++y) {
            for (int x = 20; x < 28; ++x) {
                sum += frame.image.pixel(x, y)[0];
            }
        }
        return sum / 64.0;
    };
    const auto as_is = [](scene::FrameRequest&) {};
    const auto point_light = [](scene::FrameRequest& request) {
        request.light.type = scene::LightType::point;
        request.light.position = {1.2, 0.05, 0.0};
    };
    const double reference = face_red(scene::Mode::reference, as_is);
    const double reference_point = face_red(scene::Mode::reference, point_light);
    ASSERT_GT(reference, 60.0);
    ASSERT_GT(reference_point, 60.0);
    const auto per_slice = [](scene::FrameRequest& request) {
        request.settings.light_buffer.builder = scene::LightBufferBuilder::per_slice;
    };
    const auto preintegrated = [](scene::FrameRequest& request) {
        request.settings.preintegration = true;
    };
    EXPECT_NEAR(face_red(scene::Mode::sbrc, as_is), reference, 4.0) << "multi_slice";
    EXPECT_NEAR(face_red(scene::Mode::sbrc, per_slice), reference, 4.0) << "per_slice";
    EXPECT_NEAR(face_red(scene::Mode::sbrc_cone, as_is), reference, 4.0) << "sbrc_cone";
    // Pre-integrated, segment i ends at sample i and is lit at its middle, half a step nearer the
    // light than the sample the reference lights: 99 against 90 here, where the light falls
    // steeply into the face. Its first segment, which starts on the face, is lit at its sample
    // (lit on the face, it measured 128).
    EXPECT_NEAR(face_red(scene::Mode::sbrc, preintegrated), reference, 12.0) << "preintegration";
    EXPECT_NEAR(face_red(scene::Mode::sbrc, point_light), reference_point, 4.0) << "point light";
    EXPECT_NEAR(face_red(scene::Mode::sbrc,
                         [&](scene::FrameRequest& request) {
                             point_light(request);
                             per_slice(request);
                         }),
                reference_point, 4.0)
            << "point light, per_slice";
}

// Half-angle slicing with the eye and the light on either side of the half-angle axis, its slices
// edge-on to a cut face: the light pass's fragments beside the face read a slab along the light's
// ray that reaches into what is kept, so its slices are widened by that slab (not along their
// axis, which would widen them by nothing here and drop those fragments' shadow).
TEST_F(CutTest, HalfAngleLightsACutFaceAcrossItsSlices) {
    use(test::radial_volume(32));
    scene::FrameRequest request;
    request.camera.eye = {-2.0, 0.0, 1.5};
    request.camera.target = {0.0, 0.0, 0.0};
    request.camera.up = {0.0, 0.0, 1.0};
    request.light.direction = {0.8, 0.0, 0.6};  // the half-angle axis is -x, the face's normal z
    request.light.ambient = 0.0;
    request.settings.width = request.settings.height = 48;
    request.settings.sample_distance = 1.0 / 128.0;
    request.settings.light_buffer.slices = 128;
    request.settings.light_buffer.resolution = 64;
    request.transfer_function = {
            "ball", {{0.0, {1.0, 1.0, 1.0}}}, {{0.0, 0.0}, {0.3, 0.0}, {0.35, 0.3}, {1.0, 0.3}}};
    request.cut = crop_world(glm::dvec3(-1.0), {1.0, 1.0, 0.01}, false);
    const auto face_red = [&](scene::Mode mode) {
        request.settings.mode = mode;
        const Frame frame = render(request);
        double sum = 0.0;
        for (int y = 21; y < 27; ++y) {
            for (int x = 21; x < 27; ++x) {
                sum += frame.image.pixel(x, y)[0];
            }
        }
        return sum / 36.0;
    };
    const double reference = face_red(scene::Mode::reference);
    ASSERT_GT(reference, 40.0);
    // Half-angle lights each slice before its own slab dims the light: at 128 slices that leaves
    // the face 19/255 brighter than the reference (falling as the slices grow); widened along the
    // axis, the slices left it 25 brighter.
    EXPECT_NEAR(face_red(scene::Mode::half_angle), reference, 22.0);
}

// A crop beside the volume, or a plane that keeps only what lies beyond it, leaves nothing: every
// mode draws the background.
TEST_F(CutTest, ACutThatRemovesEverythingDrawsTheBackground) {
    use(test::radial_volume(24));
    scene::Cut beyond_plane;
    beyond_plane.planes[2] = plane_world({0.55, 0.0, 0.0}, {1.0, 0.1, 0.0});
    for (const scene::Cut& cut :
         {crop_world(glm::dvec3(0.7), glm::dvec3(0.9), false), beyond_plane}) {
        for (const scene::Mode mode :
             {scene::Mode::dvr, scene::Mode::phong, scene::Mode::sbrc, scene::Mode::sbrc_shell,
              scene::Mode::sbrc_cone, scene::Mode::half_angle, scene::Mode::reference}) {
            SCOPED_TRACE(scene::to_string(mode));
            scene::FrameRequest request = receiver_scene(mode);
            request.settings.width = request.settings.height = 24;
            request.settings.light_buffer.slices = 32;
            request.settings.background = {0.2, 0.4, 0.6};
            request.transfer_function = {
                    "opaque", {{0.0, {1.0, 1.0, 1.0}}}, {{0.0, 0.5}, {1.0, 1.0}}};
            request.cut = cut;
            const Frame frame = render(request);
            for (int y = 0; y < 24; ++y) {
                for (int x = 0; x < 24; ++x) {
                    const auto pixel = frame.image.pixel(x, y);
                    ASSERT_NEAR(pixel[0], 51, 1) << x << "," << y;
                    ASSERT_NEAR(pixel[1], 102, 1) << x << "," << y;
                    ASSERT_NEAR(pixel[2], 153, 1) << x << "," << y;
                }
            }
        }
    }
}

// A plane exactly on a face between bricks of the empty-space map (8 voxels: world x = 0 in a
// 32-voxel volume), and a crop thinner than a voxel against that face: skipping the bricks the
// region leaves out must not lose the layer beside the face, so frames with and without skipping
// agree.
TEST_F(CutTest, ACutOnABrickFaceKeepsTheLayerBesideIt) {
    use(test::radial_volume(32));
    scene::Cut on_face;
    on_face.planes[0] = plane_world({0.0, 0.0, 0.0}, {1.0, 0.0, 0.0});
    const scene::Cut thin = crop_world({0.0, -1.0, -1.0}, {1.0 / 64.0, 1.0, 1.0}, false);
    for (const scene::Cut& cut : {on_face, thin}) {
        for (const scene::Mode mode : {scene::Mode::phong, scene::Mode::sbrc}) {
            SCOPED_TRACE(scene::to_string(mode));
            scene::FrameRequest request;
            request.camera = scene::orbit_camera(-70.0, 15.0, 2.4);
            request.settings.mode = mode;
            request.settings.width = request.settings.height = 48;
            request.settings.light_buffer.slices = 64;
            request.settings.light_buffer.resolution = 48;
            request.transfer_function = {"shell",
                                         {{0.0, {1.0, 1.0, 1.0}}},
                                         {{0.0, 0.0}, {0.2, 0.0}, {0.3, 0.4}, {1.0, 0.4}}};
            request.cut = cut;
            request.settings.empty_space_skipping = true;
            const Frame skipping = render(request);
            request.settings.empty_space_skipping = false;
            const Frame marching = render(request);
            auto difference = imageio::compare_images(base::to_rgba_f(skipping.image),
                                                      base::to_rgba_f(marching.image));
            ASSERT_TRUE(difference.ok());
            EXPECT_LE(difference->max_error, 2.0 / 255.0);
            double drawn = 0.0;
            for (int y = 0; y < 48; ++y) {
                for (int x = 0; x < 48; ++x) {
                    drawn = std::max(drawn, static_cast<double>(skipping.image.pixel(x, y)[0]));
                }
            }
            EXPECT_GT(drawn, 20.0) << "the layer beside the face is drawn";
        }
    }
}

// The light buffer holds the cut when the cut tissue casts no shadow: changing the cut rebuilds it
// once, moving the camera never does, and with context shadows the uncut buffer serves.
TEST_F(CutTest, TheLightBufferIsRebuiltExactlyWhenTheCutChangesWhatTheLightMeets) {
    use(test::radial_volume(24));
    scene::FrameRequest request = receiver_scene(scene::Mode::sbrc);
    request.settings.width = request.settings.height = 16;
    request.settings.light_buffer.slices = 24;
    request.settings.light_buffer.resolution = 24;
    EXPECT_EQ(render(request).report.light_buffer, LightBufferState::built);
    request.cut = crop_world(glm::dvec3(-1.0), glm::dvec3(0.1, 1.0, 1.0), false);
    EXPECT_EQ(render(request).report.light_buffer, LightBufferState::built);
    request.camera = scene::orbit_camera(40.0, 20.0, 2.5);
    EXPECT_EQ(render(request).report.light_buffer, LightBufferState::reused);
    request.cut.crop.max.x += 1.0;  // a millimetre
    EXPECT_EQ(render(request).report.light_buffer, LightBufferState::built);
    // Grown past the volume, the crop cuts nothing: the uncut volume's buffer serves it.
    const scene::Cut around = request.cut;
    request.cut.crop.max = crop_world(glm::dvec3(-1.0), glm::dvec3(1.0), false).crop.max;
    EXPECT_EQ(render(request).report.light_buffer, LightBufferState::reused);
    request.cut = around;
    EXPECT_EQ(render(request).report.light_buffer, LightBufferState::reused);
    // A plane that is off cuts nothing, wherever it lies; nor does one beside the volume.
    request.cut.planes[1] = plane_world({0.0, 0.1, 0.0}, {0.0, 1.0, 0.0});
    request.cut.planes[1].enabled = false;
    EXPECT_EQ(render(request).report.light_buffer, LightBufferState::reused);
    request.cut.planes[2] = plane_world({0.0, -0.7, 0.0}, {0.0, 1.0, 0.0});
    EXPECT_EQ(render(request).report.light_buffer, LightBufferState::reused);
    request.cut.planes[1].enabled = true;
    EXPECT_EQ(render(request).report.light_buffer, LightBufferState::built);
    // Context shadows: the light meets the whole volume, whose buffer is still held.
    const std::uint64_t builds = renderer_->light_buffer_builds();
    request.cut.casts_shadows = true;
    EXPECT_EQ(render(request).report.light_buffer, LightBufferState::reused);
    request.cut.crop.min.y += 2.0;
    EXPECT_EQ(render(request).report.light_buffer, LightBufferState::reused);
    EXPECT_EQ(renderer_->light_buffer_builds(), builds);
}

}  // namespace
}  // namespace penumbra::render
