#include <penumbra/scene/frame_request.hpp>

#include <gtest/gtest.h>

#include <limits>

namespace penumbra::scene {
namespace {

FrameRequest valid_request() {
    FrameRequest request;
    request.transfer_function = preset("grey_ramp").value();
    return request;
}

TEST(FrameRequest, DefaultsAreValid) { EXPECT_TRUE(validate(valid_request()).ok()); }

TEST(FrameRequest, RejectsEachBadFieldByName) {
    struct Case {
        const char* field;
        void (*spoil)(FrameRequest&);
    };
    const Case cases[] = {
            {"size", [](FrameRequest& r) { r.settings.width = 0; }},
            {"size", [](FrameRequest& r) { r.settings.height = 100000; }},
            {"sample_distance", [](FrameRequest& r) { r.settings.sample_distance = 0.0; }},
            {"sample_distance",
             [](FrameRequest& r) { r.settings.sample_distance = std::numeric_limits<double>::infinity(); }},
            {"opacity_unit_distance", [](FrameRequest& r) { r.settings.opacity_unit_distance = -1.0; }},
            {"early_termination", [](FrameRequest& r) { r.settings.early_termination = 1.5; }},
            {"camera", [](FrameRequest& r) { r.camera.eye.x = std::numeric_limits<double>::quiet_NaN(); }},
            {"camera", [](FrameRequest& r) { r.camera.target = r.camera.eye; }},
            {"camera.fov_y", [](FrameRequest& r) { r.camera.fov_y_degrees = 180.0; }},
            {"light.direction", [](FrameRequest& r) { r.light.direction = glm::dvec3(0.0); }},
            {"light", [](FrameRequest& r) { r.light.intensity = -1.0; }},
            {"shading", [](FrameRequest& r) { r.settings.shading.shininess = 0.0; }},
    };
    for (const auto& c : cases) {
        FrameRequest request = valid_request();
        c.spoil(request);
        const auto status = validate(request);
        ASSERT_FALSE(status.ok()) << c.field;
        EXPECT_EQ(status.error().where, c.field);
        EXPECT_EQ(status.error().code, "invalid_value");
    }
}

TEST(FrameRequest, ModeNamesRoundTrip) {
    for (Mode mode : {Mode::dvr, Mode::phong, Mode::half_angle, Mode::sbrc, Mode::sbrc_shell,
                      Mode::sbrc_cone, Mode::reference}) {
        EXPECT_EQ(parse_mode(to_string(mode)), mode);
    }
    EXPECT_FALSE(parse_mode("raytrace").has_value());
    EXPECT_EQ(parse_compositing("extinction"), Compositing::extinction);
    EXPECT_EQ(parse_raycast_stage("fragment"), RaycastStage::fragment);
}

}  // namespace
}  // namespace penumbra::scene
