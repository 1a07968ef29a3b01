// The converged truth's cache key: one truth per case, so the key must change with everything the
// truth's image depends on, and must not change with what the truth request replaces.

#include <penumbra/bench/truth.hpp>

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::bench {
namespace {

volume::Volume small_volume() {
    return volume::make_volume("head", {4, 4, 4}, glm::dvec3(1.0), std::vector<float>(64, 0.25f))
            .value();
}

scene::FrameRequest small_view() {
    scene::FrameRequest request;
    request.settings.width = 64;
    request.settings.height = 64;
    request.transfer_function = {"skin", {{0.0, {1.0, 0.8, 0.6}}}, {{0.0, 0.0}, {1.0, 0.5}}};
    return request;
}

constexpr quality::TruthMethod method{1.0 / 2048.0, 16};

TEST(TruthKey, ChangesWithEverythingTheImageDependsOn) {
    const volume::Volume volume = small_volume();
    const scene::FrameRequest view = small_view();
    const std::string key = truth_key(volume, view, method);
    const std::vector<std::pair<
            const char*,
            std::function<void(volume::Volume&, scene::FrameRequest&, quality::TruthMethod&)>>>
            changes = {
                    {"a voxel", [](auto& v, auto&, auto&) { v.data[5] = std::byte{1}; }},
                    {"the volume's name", [](auto& v, auto&, auto&) { v.name = "other"; }},
                    {"the spacing", [](auto& v, auto&, auto&) { v.spacing.z = 2.0; }},
                    {"the orientation", [](auto& v, auto&, auto&) { v.axes[0].x = -1.0; }},
                    {"the value mapping", [](auto& v, auto&, auto&) { v.rescale.slope = 2.0; }},
                    {"the view", [](auto&, auto& r, auto&) { r.camera.eye.x += 1e-9; }},
                    {"the field of view",
                     [](auto&, auto& r, auto&) { r.camera.fov_y_degrees = 31; }},
                    {"the light", [](auto&, auto& r, auto&) { r.light.direction.y = 0.5; }},
                    {"the ambient light", [](auto&, auto& r, auto&) { r.light.ambient = 0.3; }},
                    {"a TF opacity",
                     [](auto&, auto& r, auto&) { r.transfer_function.opacities[1].alpha = 0.6; }},
                    {"a TF colour",
                     [](auto&, auto& r, auto&) { r.transfer_function.colors[0].rgb.r = 0.9; }},
                    {"the TF's space",
                     [](auto&, auto& r, auto&) {
                         r.transfer_function.space = scene::PositionSpace::hounsfield;
                     }},
                    {"the width", [](auto&, auto& r, auto&) { r.settings.width = 65; }},
                    {"the height", [](auto&, auto& r, auto&) { r.settings.height = 65; }},
                    {"Blinn-Phong",
                     [](auto&, auto& r, auto&) { r.settings.phong = !r.settings.phong; }},
                    {"the compositing",
                     [](auto&, auto& r, auto&) {
                         r.settings.compositing = scene::Compositing::extinction;
                     }},
                    {"the background",
                     [](auto&, auto& r, auto&) { r.settings.background.g = 1.0; }},
                    {"the truth's distance", [](auto&, auto&, auto& m) { m.sample_distance /= 2; }},
                    {"the truth's frames", [](auto&, auto&, auto& m) { m.frames = 32; }},
            };
    for (const auto& [what, change] : changes) {
        volume::Volume changed_volume = volume;
        scene::FrameRequest changed_view = view;
        quality::TruthMethod changed_method = method;
        change(changed_volume, changed_view, changed_method);
        EXPECT_NE(truth_key(changed_volume, changed_view, changed_method), key) << what;
    }
}

TEST(TruthKey, IgnoresWhatTheTruthRequestReplaces) {
    const volume::Volume volume = small_volume();
    const scene::FrameRequest view = small_view();
    const std::string key = truth_key(volume, view, method);
    scene::FrameRequest other = view;
    other.settings.mode = scene::Mode::half_angle;
    other.settings.sample_distance = 1.0 / 64.0;
    other.settings.jitter = !view.settings.jitter;
    other.settings.empty_space_skipping = !view.settings.empty_space_skipping;
    other.settings.preintegration = !view.settings.preintegration;
    other.refinement = {true, 0};
    other.settings.light_buffer.slices = 32;
    other.settings.light_buffer.lookup = scene::LightLookup::interpolate;
    other.settings.light_buffer.slab_samples = 1;
    other.settings.scattering.cone_angle_degrees = 10.0;
    EXPECT_EQ(truth_key(volume, other, method), key);
    const scene::FrameRequest request = truth_request(view, method);
    EXPECT_EQ(request.settings.mode, scene::Mode::reference);
    EXPECT_EQ(request.settings.sample_distance, method.sample_distance);
    EXPECT_TRUE(request.settings.jitter);
    EXPECT_FALSE(request.settings.preintegration);
}

}  // namespace
}  // namespace penumbra::bench
