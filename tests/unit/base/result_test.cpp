#include <penumbra/base/result.hpp>

#include <gtest/gtest.h>

namespace penumbra::base {
namespace {

Result<int> parse_positive(int v) {
    if (v <= 0) {
        return make_error("not_positive", "value must be positive", "field");
    }
    return v;
}

TEST(Result, CarriesValueOrError) {
    auto good = parse_positive(3);
    ASSERT_TRUE(good.ok());
    EXPECT_EQ(*good, 3);

    auto bad = parse_positive(-1);
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().code, "not_positive");
    EXPECT_EQ(bad.error().to_string(), "field: value must be positive [not_positive]");
}

TEST(ResultDeathTest, ValueOfAnErrorAborts) {
    auto bad = parse_positive(0);
    EXPECT_DEATH((void)bad.value(), "Result::value\\(\\) on an error");
}

}  // namespace
}  // namespace penumbra::base
