#include "core/text_tokens.h"

#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

TEST(TextTokensTest, SplitsAtSpacesAndTabs) {
  std::vector<absl::string_view> tokens = {"stale"};
  SplitTokens("  f 1/2\t3//4   5 ", tokens);
  EXPECT_EQ(tokens, (std::vector<absl::string_view>{"f", "1/2", "3//4", "5"}));
  SplitTokens("", tokens);
  EXPECT_TRUE(tokens.empty());
}

TEST(TextTokensTest, ParsesWholeTokensOnly) {
  double d = 0;
  EXPECT_TRUE(ParseNumber(".5", d));
  EXPECT_EQ(d, 0.5);
  EXPECT_TRUE(ParseNumber("-1e-3", d));
  EXPECT_EQ(d, -1e-3);
  EXPECT_FALSE(ParseNumber("1.5x", d));
  EXPECT_FALSE(ParseNumber("", d));
  int64_t i = 0;
  EXPECT_TRUE(ParseNumber("42", i));
  EXPECT_EQ(i, 42);
  EXPECT_FALSE(ParseNumber("4.2", i));
  EXPECT_FALSE(ParseNumber("99999999999999999999", i));
}

}  // namespace
}  // namespace fitbase::core
