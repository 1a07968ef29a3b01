#include "examples.hpp"

#include <penumbra/protocol/messages.hpp>
#include <penumbra/protocol/scene_json.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace penumbra::protocol {
namespace {

scene::State preset_state(const char* preset) {
    scene::State state;
    state.frame.transfer_function = scene::preset(preset).value();
    return state;
}

Patch patch_of(const std::string& set_message) {
    auto request = parse_request(set_message, Limits{});
    EXPECT_TRUE(request.ok()) << set_message;
    return request.ok() ? std::get<Set>(request->message).patch
                        : parse_patch("{}", Limits{}).value();
}

// Sessions in many shapes: defaults, every preset, and the result of every valid set example.
std::vector<scene::State> sample_states() {
    std::vector<scene::State> states = {scene::State{}};
    for (const auto& name : scene::preset_names()) {
        states.push_back(preset_state(name.c_str()));
    }
    for (const auto& [name, text] : test::valid_examples()) {
        if (text.find("\"set\"") == std::string::npos) {
            continue;
        }
        scene::State state = preset_state("mri_brain");
        EXPECT_TRUE(apply_patch(patch_of(text), state, Limits{}).ok()) << name;
        states.push_back(state);
    }
    return states;
}

TEST(StateJson, RoundTripsThroughApplyPatch) {
    for (const scene::State& state : sample_states()) {
        const std::string json = state_to_json(state);
        SCOPED_TRACE(json);
        scene::State copy = preset_state("grey_ramp");
        const auto status = apply_patch(json, copy, Limits{});
        ASSERT_TRUE(status.ok()) << status.error().to_string();
        EXPECT_EQ(state_to_json(copy), json);
    }
}

// A session drawing a label map: its labels' styles round-trip through `state` and `set` as the
// rest do, and a patch applies all, then only, then styles by id, then blend.
TEST(StateJson, LabelStylesRoundTripAndApplyInTheirOrder) {
    scene::State state = preset_state("mri_brain");
    state.frame.labels.styles = {{.id = 1, .color = {0.8, 0.8, 0.8}},
                                 {.id = 45, .color = {0.2, 0.2, 0.8}},
                                 {.id = 46, .color = {0.5, 0.1, 0.1}}};
    ASSERT_TRUE(apply_patch(R"({"labels":{"all":{"opacity":0.5},"only":[45,46],
                                "styles":{"46":{"visible":false,"color":[1,0,0]}},"blend":0.9,
                                "alone":true}})",
                            state, Limits{})
                        .ok());
    const scene::Labels& labels = state.frame.labels;
    EXPECT_EQ(labels.styles[0].visible, false);
    EXPECT_EQ(labels.styles[1].visible, true);
    EXPECT_EQ(labels.styles[2].visible, false);
    EXPECT_EQ(labels.styles[2].color, glm::dvec3(1.0, 0.0, 0.0));
    EXPECT_EQ(labels.styles[0].opacity, 0.5);
    EXPECT_EQ(labels.blend, 0.9);
    EXPECT_TRUE(labels.alone);

    const std::string json = state_to_json(state);
    scene::State copy = preset_state("grey_ramp");
    copy.frame.labels.styles = {{.id = 1}, {.id = 45}, {.id = 46}};
    ASSERT_TRUE(apply_patch(json, copy, Limits{}).ok());
    EXPECT_EQ(state_to_json(copy), json);
    EXPECT_EQ(copy.frame.labels, labels);

    // An id the map does not hold, a colour out of range: refused at their pointers, nothing
    // changed.
    auto refused = apply_patch(R"({"labels":{"only":[45, 7]}})", copy, Limits{});
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().where, "/labels/only/1");
    refused = apply_patch(R"({"labels":{"styles":{"45":{"color":[2,0,0]}}}})", copy, Limits{});
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().where, "/labels/styles/45/color/0");
    refused = apply_patch(R"({"labels":{"only":[1,1,1,1]}})", copy, Limits{});
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, base::ErrorCode::out_of_range);
    EXPECT_EQ(copy.frame.labels, labels);
}

// Each setting of the table, of every kind, set alone to a value no default has: `state` answers
// it at its path with nothing else changed, and a value beyond its range (a name not among its
// choices, a boolean's wrong type) is refused at that path. A row that the parser or `state` leaves
// out fails here.
TEST(StateJson, EveryTableSettingRoundTripsThroughSetAndState) {
    using nlohmann::json;
    const Limits limits;
    for (const scene::Setting* setting : scene::kSettings) {
        if (!setting->held()) {
            continue;
        }
        const std::string path(setting->path);
        SCOPED_TRACE(path);
        const json::json_pointer pointer("/" + path);
        scene::State state = preset_state("ct_skin");
        const json before = json::parse(state_to_json(state));
        ASSERT_TRUE(before.contains(pointer));
        const double max = setting->max_under(scene_limits(limits));
        json value;
        json beyond;
        switch (setting->kind) {
            case scene::SettingKind::number:
                value = setting->min + 0.375 * (max - setting->min);
                beyond = max + 1.0;
                break;
            case scene::SettingKind::whole:
                value = static_cast<int>(max);
                beyond = max + 1.0;
                break;
            case scene::SettingKind::boolean:
                value = !before.at(pointer).get<bool>();
                beyond = 1;
                break;
            case scene::SettingKind::choice:
                value = setting->choices.back() == before.at(pointer) ? setting->choices.front()
                                                                      : setting->choices.back();
                beyond = "none_of_these";
                break;
            case scene::SettingKind::vector:
                value = json::array({0.25 * max, 0.5 * max, 0.75 * max});
                beyond = json::array({0.0, max + 1.0, 0.0});
                break;
            case scene::SettingKind::size:
                value = json::array({static_cast<int>(max), 3});
                beyond = json::array({3, static_cast<int>(max) + 1});
                break;
        }
        ASSERT_NE(before.at(pointer).dump(), value.dump());

        json patch = json::object();
        patch[pointer] = value;
        const auto status = apply_patch(patch.dump(), state, limits);
        ASSERT_TRUE(status.ok()) << status.error().to_string();
        json expected = before;
        expected[pointer] = value;
        EXPECT_EQ(state_to_json(state), expected.dump());

        patch[pointer] = beyond;
        const auto refused = apply_patch(patch.dump(), state, limits);
        ASSERT_FALSE(refused.ok());
        EXPECT_TRUE(refused.error().where.starts_with("/" + path)) << refused.error().where;
        EXPECT_EQ(state_to_json(state), expected.dump());
    }
}

TEST(StateJson, IsAValidSetOnItsOwn) {
    const std::string message =
            R"({"v":1,"type":"set",)" + state_to_json(preset_state("ct_skin")).substr(1);
    EXPECT_TRUE(parse_request(message, Limits{}).ok()) << message;
}

TEST(ApplyPatch, ChangesOnlyTheMembersItNames) {
    scene::State state = preset_state("ct_bone");
    const scene::State before = state;
    ASSERT_TRUE(
            apply_patch(R"({"light":{"intensity":2.5},"settings":{"light_buffer":{"slices":64}}})",
                        state, Limits{})
                    .ok());
    EXPECT_EQ(state.frame.light.intensity, 2.5);
    EXPECT_EQ(state.frame.settings.light_buffer.slices, 64);
    state.frame.light.intensity = before.frame.light.intensity;
    state.frame.settings.light_buffer.slices = before.frame.settings.light_buffer.slices;
    EXPECT_EQ(state_to_json(state), state_to_json(before));
}

TEST(ApplyPatch, ReplacesTheWholeTransferFunction) {
    scene::State state = preset_state("ct_bone");
    ASSERT_TRUE(apply_patch(R"({"transfer_function":{"opacities":[{"x":0.5,"alpha":1}]}})", state,
                            Limits{})
                        .ok());
    EXPECT_TRUE(state.frame.transfer_function.colors.empty());
    ASSERT_EQ(state.frame.transfer_function.opacities.size(), 1U);
    EXPECT_EQ(state.frame.transfer_function.name, "custom");
    ASSERT_TRUE(
            apply_patch(R"({"transfer_function":{"preset":"mri_skin"}})", state, Limits{}).ok());
    EXPECT_EQ(state_to_json(state), state_to_json(preset_state("mri_skin")));
}

TEST(ApplyPatch, LeavesStateUnchangedWhenALaterPartFails) {
    scene::State state = preset_state("mri_skin");
    const std::string before = state_to_json(state);
    // camera, light and transfer_function are valid and applied first; settings then fails.
    const auto status = apply_patch(
            R"({"camera":{"fov":45},"light":{"intensity":3},
                "transfer_function":{"preset":"ct_bone"},
                "settings":{"size":[640,480],"mode":"mip"}})",
            state, Limits{});
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.error().where, "/settings/mode");
    EXPECT_EQ(state_to_json(state), before);

    // A failure found only when the whole state is checked (eye == target) changes nothing either.
    const auto degenerate =
            apply_patch(R"({"light":{"intensity":3},"camera":{"eye":[0,0,0]}})", state, Limits{});
    ASSERT_FALSE(degenerate.ok());
    EXPECT_EQ(degenerate.error().code, base::ErrorCode::invalid_value);
    EXPECT_EQ(degenerate.error().where, "/camera");
    EXPECT_EQ(state_to_json(state), before);
}

// The crop box travels in patient millimetres as it was set, and a box that is inverted or empty
// on any axis is refused whole, naming the box.
TEST(ApplyPatch, TakesACropBoxAndRefusesAnInvertedOne) {
    scene::State state = preset_state("mri_skin");
    ASSERT_TRUE(apply_patch(R"({"cut":{"crop":{"enabled":true,"min":[-20.5,-100,-60],
                                               "max":[0,80,90]},"casts_shadows":true}})",
                            state, Limits{})
                        .ok());
    EXPECT_TRUE(state.frame.cut.crop.enabled);
    EXPECT_EQ(state.frame.cut.crop.min, glm::dvec3(-20.5, -100.0, -60.0));
    EXPECT_EQ(state.frame.cut.crop.max, glm::dvec3(0.0, 80.0, 90.0));
    EXPECT_TRUE(state.frame.cut.casts_shadows);
    const std::string before = state_to_json(state);
    const auto inverted = apply_patch(R"({"cut":{"crop":{"max":[-30,80,90]}}})", state, Limits{});
    ASSERT_FALSE(inverted.ok());
    EXPECT_EQ(inverted.error().code, base::ErrorCode::invalid_value);
    EXPECT_EQ(inverted.error().where, "/cut/crop");
    EXPECT_EQ(state_to_json(state), before);
}

// A clip plane travels as set (its normal any length but zero); a zero normal is refused naming
// the plane's normal, and the state is left as it was.
TEST(ApplyPatch, TakesAClipPlaneAndRefusesAZeroNormal) {
    scene::State state = preset_state("mri_skin");
    ASSERT_TRUE(apply_patch(R"({"cut":{"plane_3":{"enabled":true,"point":[1,-2,30.5],
                                                  "normal":[0,0.6,-0.8]}}})",
                            state, Limits{})
                        .ok());
    const scene::ClipPlane& plane = state.frame.cut.planes[2];
    EXPECT_TRUE(plane.enabled);
    EXPECT_EQ(plane.point, glm::dvec3(1.0, -2.0, 30.5));
    EXPECT_EQ(plane.normal, glm::dvec3(0.0, 0.6, -0.8));
    EXPECT_FALSE(state.frame.cut.planes[0].enabled);
    const std::string before = state_to_json(state);
    EXPECT_NE(
            before.find(
                    R"("plane_3":{"enabled":true,"normal":[0.0,0.6,-0.8],"point":[1.0,-2.0,30.5]})"),
            std::string::npos)
            << before;
    const auto zero = apply_patch(R"({"cut":{"plane_6":{"normal":[0,0,0]}}})", state, Limits{});
    ASSERT_FALSE(zero.ok());
    EXPECT_EQ(zero.error().code, base::ErrorCode::invalid_value);
    EXPECT_EQ(zero.error().where, "/cut/plane_6/normal");
    const auto long_normal =
            apply_patch(R"({"cut":{"plane_1":{"normal":[0,0,2]}}})", state, Limits{});
    ASSERT_FALSE(long_normal.ok());
    EXPECT_EQ(long_normal.error().code, base::ErrorCode::out_of_range);
    EXPECT_EQ(long_normal.error().where, "/cut/plane_1/normal/2");
    EXPECT_EQ(state_to_json(state), before);
}

TEST(ApplyPatch, RejectsMalformedAndNonObjectPatches) {
    scene::State state;
    const auto malformed = apply_patch("{", state, Limits{});
    ASSERT_FALSE(malformed.ok());
    EXPECT_EQ(malformed.error().code, base::ErrorCode::malformed_json);
    const auto array = apply_patch("[]", state, Limits{});
    ASSERT_FALSE(array.ok());
    EXPECT_EQ(array.error().code, base::ErrorCode::invalid_value);
    EXPECT_EQ(array.error().where, "/");
}

TEST(ApplyPatch, NamesSettingsThatBreakTheLimitsByTheirPointer) {
    // A state valid under the defaults checked against smaller limits: the whole-state check
    // names the settings member as a pointer into a set message.
    Limits small;
    small.max_slices = 16;
    scene::State state = preset_state("grey_ramp");
    const auto status = apply_patch(R"({"camera":{"fov":40}})", state, small);
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.error().code, base::ErrorCode::invalid_value);
    EXPECT_EQ(status.error().where, "/settings/light_buffer/slices");
}

TEST(ParseRequest, AcceptsPatchesUnderLimitsBelowTheDefaults) {
    Limits small;
    small.max_image_side = 256;
    small.max_slices = 16;
    small.max_light_resolution = 64;
    EXPECT_TRUE(parse_request(R"({"v":1,"type":"set","camera":{"fov":40}})", small).ok());
}

TEST(ApplyPatch, OrbitsAroundThePatchTargetOrTheCurrentOne) {
    scene::State state = preset_state("grey_ramp");
    ASSERT_TRUE(apply_patch(R"({"camera":{"orbit":{"azimuth":90,"elevation":0,"distance":2},
                                          "target":[0.1,0,0]}})",
                            state, Limits{})
                        .ok());
    const scene::Camera& camera = state.frame.camera;
    EXPECT_NEAR(glm::distance(camera.eye, glm::dvec3(2.1, 0.0, 0.0)), 0.0, 1e-12);
    EXPECT_EQ(camera.target, glm::dvec3(0.1, 0.0, 0.0));

    ASSERT_TRUE(apply_patch(R"({"camera":{"orbit":{"azimuth":0,"distance":1.5}}})", state, Limits{})
                        .ok());
    EXPECT_EQ(camera.target, glm::dvec3(0.1, 0.0, 0.0));
    EXPECT_NEAR(glm::distance(camera.eye, glm::dvec3(0.1, 1.5, 0.0)), 0.0, 1e-12);
    EXPECT_EQ(camera.up, glm::dvec3(0.0, 0.0, 1.0));
}

// A named view looks from that side of the patient at the camera's distance from its target,
// keeping the field of view.
TEST(ApplyPatch, NamedViewsLookFromTheirSideAtTheCurrentDistance) {
    scene::State state = preset_state("grey_ramp");
    ASSERT_TRUE(apply_patch(R"({"camera":{"orbit":{"azimuth":40,"elevation":20,"distance":3},
                                          "target":[0.1,0,0],"fov":45}})",
                            state, Limits{})
                        .ok());
    ASSERT_TRUE(apply_patch(R"({"camera":{"view":"left"}})", state, Limits{}).ok());
    const scene::Camera& camera = state.frame.camera;
    EXPECT_NEAR(glm::distance(camera.eye, glm::dvec3(-2.9, 0.0, 0.0)), 0.0, 1e-12);
    EXPECT_EQ(camera.target, glm::dvec3(0.1, 0.0, 0.0));
    EXPECT_EQ(camera.up, glm::dvec3(0.0, 0.0, 1.0));
    EXPECT_EQ(camera.fov_y_degrees, 45.0);
    ASSERT_TRUE(apply_patch(R"({"camera":{"view":"superior","target":[0,0,0]}})", state, Limits{})
                        .ok());
    EXPECT_NEAR(glm::distance(camera.eye, glm::dvec3(0.0, 0.0, 3.0)), 0.0, 1e-12);
    EXPECT_EQ(camera.up, glm::dvec3(0.0, 1.0, 0.0));

    const auto unknown = apply_patch(R"({"camera":{"view":"front"}})", state, Limits{});
    ASSERT_FALSE(unknown.ok());
    EXPECT_EQ(unknown.error().where, "/camera/view");
    EXPECT_NE(unknown.error().message.find("anterior, posterior"), std::string::npos);
    const auto with_eye =
            apply_patch(R"({"camera":{"view":"left","eye":[0,3,0]}})", state, Limits{});
    ASSERT_FALSE(with_eye.ok());
    EXPECT_EQ(with_eye.error().where, "/camera/view");
}

TEST(ApplyPatch, OrbitKeepsTheFieldOfView) {
    scene::State state = preset_state("grey_ramp");
    ASSERT_TRUE(apply_patch(R"({"camera":{"fov":50}})", state, Limits{}).ok());
    ASSERT_TRUE(apply_patch(R"({"camera":{"orbit":{"azimuth":30}}})", state, Limits{}).ok());
    EXPECT_EQ(state.frame.camera.fov_y_degrees, 50.0);
}

TEST(ApplyPatch, NamesADecreasingTransferFunctionPoint) {
    scene::State state = preset_state("grey_ramp");
    const auto status = apply_patch(
            R"({"transfer_function":{"colors":[{"x":0.5,"rgb":[1,1,1]},
                                               {"x":0.25,"rgb":[0,0,0]}]}})",
            state, Limits{});
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.error().code, base::ErrorCode::invalid_value);
    EXPECT_EQ(status.error().where, "/transfer_function/colors/1");
}

// A transfer function's space is a name of scene's table, or "data" in a file, which is read over
// the volume's range into normalised positions; any other name is refused, naming the choices.
TEST(TransferFunctionJson, SpacesAreTheTablesNamesAndDataInFiles) {
    scene::State state;
    ASSERT_TRUE(apply_patch(R"({"transfer_function":{"space":"hounsfield",
                               "opacities":[{"x":-500,"alpha":0}]}})",
                            state, Limits{}));
    EXPECT_EQ(state.frame.transfer_function.space, scene::PositionSpace::hounsfield);
    const auto kelvin = apply_patch(R"({"transfer_function":{"space":"kelvin"}})", state, Limits{});
    ASSERT_FALSE(kelvin.ok());
    EXPECT_EQ(kelvin.error().where, "/transfer_function/space");
    EXPECT_EQ(kelvin.error().message, "expected normalized, hounsfield or data");
    const auto without_range =
            apply_patch(R"({"transfer_function":{"space":"data"}})", state, Limits{});
    ASSERT_FALSE(without_range.ok());
    EXPECT_EQ(without_range.error().where, "/transfer_function/space");
    const auto from_file =
            parse_transfer_function(R"({"space":"data","opacities":[{"x":50,"alpha":1}]})",
                                    std::pair{0.0, 200.0}, "tf.json");
    ASSERT_TRUE(from_file.ok()) << from_file.error().to_string();
    EXPECT_EQ(from_file->space, scene::PositionSpace::normalized);
    EXPECT_DOUBLE_EQ(from_file->opacities.at(0).x, 0.25);
}

}  // namespace
}  // namespace penumbra::protocol

namespace penumbra::protocol {
namespace {

// Found by fuzz_protocol_patch: an orbit around a far target put the eye beyond ±1000, so the
// state sent back to clients held an eye that `set` refuses.
TEST(ApplyPatch, AnOrbitThatPutsTheEyeOutOfRangeIsRefused) {
    scene::State state;
    const auto status = apply_patch(
            R"({"camera":{"target":[1000,1000,0],"orbit":{"azimuth":90,"elevation":45,"distance":100}}})",
            state, Limits{});
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.error().code, base::ErrorCode::out_of_range);
    EXPECT_EQ(status.error().where, "/camera/orbit/distance");
    ASSERT_TRUE(apply_patch(R"({"camera":{"target":[900,0,0],"orbit":{"distance":100}}})", state,
                            Limits{})
                        .ok());
    scene::State again;
    EXPECT_TRUE(apply_patch(state_to_json(state), again, Limits{}).ok());
}

}  // namespace
}  // namespace penumbra::protocol
