#include <penumbra/cli/transfer_function_file.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace penumbra::cli {
namespace {

const volume::ValueRange range{0.0, 200.0};

std::filesystem::path write_temp(const std::string& name, const std::string& text) {
    const auto path = std::filesystem::temp_directory_path() /
                      ("penumbra_tf_" + std::to_string(::getpid()) + "_" + name);
    std::ofstream(path) << text;
    return path;
}

TEST(TransferFunctionFile, LoadsDataSpacePositionsIntoTheVolumeRange) {
    const auto path = write_temp(
            "data.json",
            R"({"space":"data","opacities":[{"x":50,"alpha":0.0},{"x":150,"alpha":1.0}]})");
    auto tf = load_transfer_function(path.string(), range);
    std::filesystem::remove(path);
    ASSERT_TRUE(tf.ok()) << tf.error().to_string();
    EXPECT_DOUBLE_EQ(tf->opacities[0].x, 0.25);
    EXPECT_DOUBLE_EQ(tf->opacities[1].x, 0.75);
}

TEST(TransferFunctionFile, ErrorsNameTheFileAndTheField) {
    const auto path = write_temp("bad.json", R"({"opacities":[{"x":0.5,"alpha":2}]})");
    auto tf = load_transfer_function(path.string(), range);
    std::filesystem::remove(path);
    ASSERT_FALSE(tf.ok());
    EXPECT_EQ(tf.error().where, path.string() + "/opacities/0/alpha");
    EXPECT_EQ(tf.error().code, base::ErrorCode::out_of_range);
}

TEST(TransferFunctionFile, LoadsPresetsByNameAndReportsMissingFiles) {
    EXPECT_TRUE(load_transfer_function("ct_bone", range).ok());
    EXPECT_EQ(load_transfer_function("/nonexistent/tf.json", range).error().code,
              base::ErrorCode::not_found);
}

}  // namespace
}  // namespace penumbra::cli
