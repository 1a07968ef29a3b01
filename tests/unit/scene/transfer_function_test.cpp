#include <penumbra/scene/transfer_function.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>

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

// The value entry i of a table baked over [min, max] stands for.
double table_value(const ValueDomain& domain, std::size_t i, std::size_t size) {
    return domain.min +
           static_cast<double>(i) / static_cast<double>(size - 1) * (domain.max - domain.min);
}

TEST(TransferFunction, BonePresetSelectsBoneInHounsfieldUnitsOnEveryCtRange) {
    // Ranges real CTs have: 12-bit scanners, an outside-the-scan value of -2048 or -3024, a
    // metal implant at the top of int16, a cropped volume.
    const TransferFunction bone = preset("ct_bone").value();
    for (const auto& [min, max] : {std::pair{-1024.0, 3071.0},
                                   {-2048.0, 4095.0},
                                   {-3024.0, 3071.0},
                                   {-1024.0, 32767.0},
                                   {-1000.0, 2000.0},
                                   {-200.0, 1500.0}}) {
        const ValueDomain domain{min, max, true};
        const auto table = bake(bone, default_table_size, domain);
        for (std::size_t i = 0; i < table.size(); ++i) {
            const double hu = table_value(domain, i, table.size());
            if (hu >= 300.0) {
                EXPECT_GE(table[i].a, 0.5f) << hu << " HU on " << min << ".." << max;
            } else if (hu < 150.0) {
                EXPECT_EQ(table[i].a, 0.0f) << hu << " HU on " << min << ".." << max;
            }
        }
    }
}

TEST(TransferFunction, CtPresetsReadANonHounsfieldVolumeAsTheTwelveBitCtRange) {
    // A CT stored as a raw int16 file is not marked as HU: its range is taken as -1024..3071.
    const auto table = bake(preset("ct_bone").value(), default_table_size, {0.0, 255.0, false});
    EXPECT_EQ(table, bake(preset("ct_bone").value(), default_table_size, nominal_ct_domain));
}

TEST(TransferFunction, EveryCtPresetIsInHounsfieldUnitsAndSeparatesTissues) {
    for (const std::string& name : hounsfield_preset_names()) {
        const TransferFunction tf = preset(name).value();
        EXPECT_EQ(tf.space, PositionSpace::hounsfield) << name;
        EXPECT_TRUE(validate(tf).ok()) << name;
        EXPECT_EQ(tf.evaluate(-1000.0).a, 0.0) << name << " hides air";
    }
    EXPECT_GT(preset("ct_lung").value().evaluate(-700.0).a, 0.0);
    EXPECT_EQ(preset("ct_lung").value().evaluate(40.0).a, 0.0);
    EXPECT_GT(preset("ct_skin").value().evaluate(-100.0).a, 0.3);
    EXPECT_GT(preset("ct_soft_tissue").value().evaluate(40.0).a, 0.0);
    EXPECT_GT(preset("ct_angio").value().evaluate(300.0).a, 0.5);
    EXPECT_EQ(preset("ct_angio").value().evaluate(40.0).a, 0.0);
}

TEST(TransferFunction, ValidateBoundsHounsfieldPositions) {
    TransferFunction tf = preset("ct_bone").value();
    tf.opacities.back().x = 2.0 * max_hounsfield_position;
    EXPECT_EQ(validate(tf).error().where, "transfer_function.opacities[3]");
}

TEST(TransferFunction, EveryPresetIsValidAndUnknownNamesAreListed) {
    for (const auto& name : preset_names()) {
        auto tf = preset(name);
        ASSERT_TRUE(tf.ok()) << name;
        EXPECT_TRUE(validate(*tf).ok()) << name;
        const auto table = bake(*tf, default_table_size, nominal_ct_domain);
        EXPECT_TRUE(std::any_of(table.begin(), table.end(), [](auto e) { return e.a > 0.0f; }))
                << name << " shows something";
    }
    auto unknown = preset("nope");
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().message.find("mri_skin"), std::string::npos);
}

}  // namespace
}  // namespace penumbra::scene
