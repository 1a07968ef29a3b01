// Secrets are read from a file or the environment, never the command line, and compared in
// constant time.

#include <penumbra/base/secret.hpp>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace penumbra::base {
namespace {

constexpr const char* variable = "PENUMBRA_SECRET_TEST_VALUE";

std::filesystem::path secret_file(const std::string& name, const std::string& text) {
    const auto path = std::filesystem::temp_directory_path() / name;
    std::ofstream(path) << text;
    return path;
}

TEST(Secret, AFileWinsOverTheEnvironmentAndLosesItsTrailingNewline) {
    ::setenv(variable, "from-env", 1);
    const auto path = secret_file("penumbra_secret_test_a", "s3cret \n");
    EXPECT_EQ(read_secret(path, variable, "--token-file").value(), "s3cret");
    EXPECT_EQ(read_secret(std::nullopt, variable, "--token-file").value(), "from-env");
    ::unsetenv(variable);
    EXPECT_EQ(read_secret(std::nullopt, variable, "--token-file").value(), "");
    std::filesystem::remove(path);
}

TEST(Secret, AMissingFileOrAnEmptySecretIsAnErrorNamingItsSource) {
    auto missing = read_secret("/nonexistent/penumbra-token", variable, "--token-file");
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().code, base::ErrorCode::not_found);
    EXPECT_EQ(missing.error().where, "--token-file");
    const auto blank = secret_file("penumbra_secret_test_b", "\n\n");
    EXPECT_EQ(read_secret(blank, variable, "--token-file").error().where, "--token-file");
    std::filesystem::remove(blank);
    ::setenv(variable, " ", 1);
    EXPECT_EQ(read_secret(std::nullopt, variable, "--token-file").error().where, variable);
    ::unsetenv(variable);
}

TEST(Secret, ComparesEqualSecretsOnly) {
    EXPECT_TRUE(same_secret("abc", "abc"));
    EXPECT_FALSE(same_secret("abc", "abd"));
    EXPECT_FALSE(same_secret("abc", "abcd"));
}

}  // namespace
}  // namespace penumbra::base
