#include "load_options.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace penumbra::app {
namespace {

std::filesystem::path write_temp(const std::string& name, const std::string& text) {
    const auto path = std::filesystem::temp_directory_path() /
                      ("penumbra_load_" + std::to_string(::getpid()) + "_" + name);
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

// `penumbra load` with `args`: the run it would make, or its error.
base::Result<net::LoadConfig> load_config(const std::vector<std::string>& args) {
    LoadOptions o;
    auto parsed = cli::parse_options(args, load_options(o));
    if (!parsed) {
        return parsed.error();
    }
    if (auto status = finish_load_options(*parsed, o); !status) {
        return status.error();
    }
    return o.config;
}

// The token file is read as serve reads its secrets: the line end an editor or `echo` leaves,
// LF or CRLF, is no part of the token the server compares.
TEST(LoadOptions, TokenFileLineEndsAreNoPartOfTheToken) {
    for (const std::string& text :
         std::vector<std::string>{"s3cret", "s3cret\n", "s3cret\r\n", "s3cret  \n\n"}) {
        const auto file = write_temp("token", text);
        auto config = load_config({"--port", "8080", "--token-file", file.string()});
        std::filesystem::remove(file);
        ASSERT_TRUE(config.ok()) << config.error().to_string();
        EXPECT_EQ(config->token, "s3cret") << "file text of " << text.size() << " bytes";
    }
}

TEST(LoadOptions, AMissingOrBlankTokenFileIsRefusedNamingIt) {
    const auto blank = write_temp("blank", "\r\n");
    for (const std::string& path : {blank.string(), std::string("/nonexistent/token")}) {
        auto config = load_config({"--port", "8080", "--token-file", path});
        ASSERT_FALSE(config.ok()) << path;
        EXPECT_EQ(config.error().message, "--token-file: cannot read a token from '" + path + "'");
    }
    std::filesystem::remove(blank);
}

TEST(LoadOptions, WithoutATokenFileNoTokenIsSent) {
    auto config = load_config({"--port", "8080", "--clients", "3", "--seconds", "1/2"});
    ASSERT_TRUE(config.ok()) << config.error().to_string();
    EXPECT_EQ(config->token, "");
    EXPECT_EQ(config->port, 8080);
    EXPECT_EQ(config->clients, 3);
    EXPECT_DOUBLE_EQ(config->seconds, 0.5);
}

}  // namespace
}  // namespace penumbra::app
