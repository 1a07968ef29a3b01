#include <penumbra/scene/transfer_function.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace penumbra::scene {
namespace {

TransferFunction two_point_ramp() {
    return {"ramp", {{0.2, {0.0, 0.0, 0.0}}, {0.6, {1.0, 0.5, 0.0}}}, {{0.2, 0.0}, {0.6, 0.8}}};
}

TEST(TransferFunction, InterpolatesLinearlyBetweenPoints) {
    const glm::dvec4 mid = two_point_ramp().evaluate(0.4);
    EXPECT_DOUBLE_EQ(mid.r, 0.5);
    EXPECT_DOUBLE_EQ(mid.g, 0.25);
    EXPECT_DOUBLE_EQ(mid.a, 0.4);
}

TEST(TransferFunction, IsConstantBeyondTheEnds) {
    const TransferFunction tf = two_point_ramp();
    EXPECT_DOUBLE_EQ(tf.evaluate(0.0).a, 0.0);
    EXPECT_DOUBLE_EQ(tf.evaluate(1.0).a, 0.8);
    EXPECT_DOUBLE_EQ(tf.evaluate(1.0).r, 1.0);
}

TEST(TransferFunction, EmptyIsTransparentBlack) {
    const TransferFunction empty{"empty", {}, {}};
    EXPECT_EQ(empty.evaluate(0.5), glm::dvec4(0.0));
}

TEST(TransferFunction, StepWithEqualPositionsJumps) {
    const TransferFunction step{"step", {}, {{0.5, 0.0}, {0.5, 1.0}}};
    EXPECT_DOUBLE_EQ(step.evaluate(0.49).a, 0.0);
    EXPECT_DOUBLE_EQ(step.evaluate(0.51).a, 1.0);
}

TEST(TransferFunction, BakeSamplesEndpointsExactly) {
    const auto table = bake(two_point_ramp(), 11);
    ASSERT_EQ(table.size(), 11u);
    EXPECT_FLOAT_EQ(table[0].a, 0.0f);
    EXPECT_FLOAT_EQ(table[4].a, 0.4f);  // x = 0.4
    EXPECT_FLOAT_EQ(table[10].a, 0.8f);
}

TEST(TransferFunction, ValidateRejectsOutOfRangeAndUnsortedPoints) {
    TransferFunction tf = two_point_ramp();
    EXPECT_TRUE(validate(tf).ok());
    tf.opacities[1].alpha = 1.5;
    EXPECT_EQ(validate(tf).error().where, "transfer_function.opacities[1]");
    tf = two_point_ramp();
    tf.colors[0].x = 0.9;
    EXPECT_EQ(validate(tf).error().where, "transfer_function.colors[1]");
    tf = two_point_ramp();
    tf.colors[1].rgb.g = std::nan("");
    EXPECT_FALSE(validate(tf).ok());
}

TEST(TransferFunction, EveryPresetIsValidAndUnknownNamesAreListed) {
    for (const auto& name : preset_names()) {
        auto tf = preset(name);
        ASSERT_TRUE(tf.ok()) << name;
        EXPECT_TRUE(validate(*tf).ok()) << name;
        EXPECT_GT(tf->evaluate(1.0).a, 0.0) << name;
    }
    auto unknown = preset("nope");
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().message.find("mri_skin"), std::string::npos);
}

}  // namespace
}  // namespace penumbra::scene
