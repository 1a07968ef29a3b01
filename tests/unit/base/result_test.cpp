#include <penumbra/base/result.hpp>

#include <gtest/gtest.h>

#include <sstream>

namespace penumbra::base {
namespace {

Result<int> parse_positive(int v) {
    if (v <= 0) {
        return make_error(base::ErrorCode::invalid_value, "value must be positive", "field");
    }
    return v;
}

TEST(Result, CarriesValueOrError) {
    auto good = parse_positive(3);
    ASSERT_TRUE(good.ok());
    EXPECT_EQ(*good, 3);

    auto bad = parse_positive(-1);
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().code, base::ErrorCode::invalid_value);
    EXPECT_EQ(bad.error().to_string(), "field: value must be positive [invalid_value]");
}

// Each code reads back from its name, and prints as it (test failures and logs show names).
TEST(ErrorCode, IsNamedByItsTable) {
    for (const EnumName<ErrorCode>& row : kErrorCodeNames) {
        EXPECT_EQ(parse_name<ErrorCode>(row.name), row.value);
        std::ostringstream printed;
        printed << row.value;
        EXPECT_EQ(printed.str(), row.name);
    }
    EXPECT_EQ(name_of(ErrorCode::too_much_work), "too_much_work");
    EXPECT_EQ(parse_name<ErrorCode>("no_such_code"), std::nullopt);
}

TEST(ResultDeathTest, ValueOfAnErrorAborts) {
    auto bad = parse_positive(0);
    EXPECT_DEATH((void)bad.value(), "Result::value\\(\\) on an error");
}

}  // namespace
}  // namespace penumbra::base
