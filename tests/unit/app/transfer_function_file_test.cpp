#include <gtest/gtest.h>

#include "transfer_function_file.hpp"

namespace penumbra::app {
namespace {

const volume::ValueRange range{0.0, 200.0};

TEST(TransferFunctionFile, ParsesNormalisedAndDataPositions) {
    auto normalized = parse_transfer_function_json(
            R"({"name":"t","colors":[{"x":0.5,"rgb":[1,0,0]}],"opacities":[{"x":0.25,"alpha":0.5}]})",
            range, "t.json");
    ASSERT_TRUE(normalized.ok()) << normalized.error().to_string();
    EXPECT_EQ(normalized->name, "t");
    EXPECT_DOUBLE_EQ(normalized->opacities[0].x, 0.25);

    auto data = parse_transfer_function_json(
            R"({"space":"data","opacities":[{"x":50,"alpha":0.0},{"x":150,"alpha":1.0}]})", range,
            "d.json");
    ASSERT_TRUE(data.ok());
    EXPECT_DOUBLE_EQ(data->opacities[0].x, 0.25);
    EXPECT_DOUBLE_EQ(data->opacities[1].x, 0.75);
}

TEST(TransferFunctionFile, NamesTheOffendingField) {
    struct Case {
        const char* json;
        const char* where;
    };
    const Case cases[] = {
            {"[1,2]", "f.json"},
            {"{not json", "f.json"},
            {R"({"space":"log"})", "f.json.space"},
            {R"({"opacities":[{"x":0.1}]})", "f.json.opacities[0].alpha"},
            {R"({"colors":[{"x":0.1,"rgb":[1,0]}]})", "f.json.colors[0].rgb"},
            {R"({"opacities":[{"x":0.5,"alpha":2}]})", "f.json: transfer_function.opacities[0]"},
    };
    for (const auto& c : cases) {
        auto tf = parse_transfer_function_json(c.json, range, "f.json");
        ASSERT_FALSE(tf.ok()) << c.json;
        EXPECT_EQ(tf.error().where, c.where) << c.json;
    }
}

TEST(TransferFunctionFile, LoadsPresetsByNameAndReportsMissingFiles) {
    EXPECT_TRUE(load_transfer_function("ct_bone", range).ok());
    EXPECT_EQ(load_transfer_function("/nonexistent/tf.json", range).error().code, "not_found");
}

}  // namespace
}  // namespace penumbra::app
