// Lists and numbers as typed on a command line.

#include <penumbra/base/text.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace penumbra::base {
namespace {

TEST(Text, SplitTrimsItemsAndDropsEmptyOnes) {
    EXPECT_EQ(split_list("a, b,,c "), (std::vector<std::string>{"a", "b", "c"}));
    EXPECT_EQ(split_list("10,45; 100,20", ';'), (std::vector<std::string>{"10,45", "100,20"}));
    EXPECT_TRUE(split_list("").empty());
    EXPECT_TRUE(split_list(" , ").empty());
}

TEST(Text, NumbersMayBeFractionsAndMustBeFinite) {
    EXPECT_DOUBLE_EQ(parse_number("1/512").value(), 1.0 / 512.0);
    EXPECT_DOUBLE_EQ(parse_number("-3/4").value(), -0.75);
    EXPECT_DOUBLE_EQ(parse_number("2.5").value(), 2.5);
    for (const char* bad : {"1/0", "1/", "/2", "1/2/3", "nan", "inf", "", " 1", "1x"}) {
        EXPECT_FALSE(parse_number(bad).has_value()) << bad;
    }
}

TEST(Text, NumberListsNameTheItemThatIsNotANumber) {
    EXPECT_EQ(parse_numbers("1/2,3").value(), (std::vector<double>{0.5, 3.0}));
    auto bad = parse_numbers("1,x,3", "--budget-ms");
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().message, "'x' is not a finite number");
    EXPECT_EQ(bad.error().where, "--budget-ms");
    EXPECT_EQ(bad.error().code, base::ErrorCode::invalid_argument);
    EXPECT_FALSE(parse_numbers("").ok());
    EXPECT_FALSE(parse_numbers("1,,2").ok());
}

TEST(Text, ValidUtf8KeepsWholeCharactersAndMarksStrayBytes) {
    EXPECT_EQ(valid_utf8("Precentral_L", 256), "Precentral_L");
    EXPECT_EQ(valid_utf8("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\xa7\xa0", 256),
              "caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\xa7\xa0");
    EXPECT_EQ(valid_utf8("caf\xe9", 256), "caf?");           // Latin-1
    EXPECT_EQ(valid_utf8("\xc0\xaf", 256), "??");            // an overlong '/'
    EXPECT_EQ(valid_utf8("\xed\xa0\x80", 256), "???");       // a surrogate
    EXPECT_EQ(valid_utf8("\xf4\x90\x80\x80", 256), "????");  // beyond U+10FFFF
    EXPECT_EQ(valid_utf8("ab\xc3\xa9", 3), "ab");            // not half a character
    EXPECT_EQ(valid_utf8("\xe2\x82", 256), "??");            // cut short
}

}  // namespace
}  // namespace penumbra::base
