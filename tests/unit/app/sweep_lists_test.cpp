#include "sweep_lists.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace penumbra::app {
namespace {

cli::po::options_description list_options() {
    cli::po::options_description options = cli::option_group("test");
    options.add_options()("slices-list", cli::po::value<Counts>(), "counts");
    return options;
}

TEST(SweepLists, CountsAreWholeNumbersInRangeEachOnce) {
    auto parsed = cli::parse_options({"--slices-list", "64,128,64"}, list_options());
    ASSERT_TRUE(parsed.ok()) << parsed.error().to_string();
    EXPECT_EQ((*parsed)["slices-list"].as<Counts>().values, (std::vector<int>{64, 128}));
    for (const char* bad : {"0", "1.5", "65537", "x", "64,x", ""}) {
        auto counts = cli::parse_options({"--slices-list", bad}, list_options());
        ASSERT_FALSE(counts.ok()) << bad;
        EXPECT_EQ(counts.error().where, "--slices-list") << bad;
    }
}

}  // namespace
}  // namespace penumbra::app
