#include "core/text_tokens.h"

#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "core/test_support.h"
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

TEST(TextTokensTest, VisitsDataLinesWithTheirNumbers) {
  std::vector<std::string> seen;
  const absl::string_view text = "# header\n\n  v 1 2 # note\n\t# indented comment\nf 1\n";
  ASSERT_TRUE(ForEachDataLine(text, "a.obj", CommentStyle::kTrailing, [&](const TextLine& line) {
                seen.push_back(absl::StrCat(line.number, ":", line.text, ":", line.tokens->size()));
                return absl::OkStatus();
              }).ok());
  EXPECT_EQ(seen, (std::vector<std::string>{"3:v 1 2:3", "5:f 1:2"}));
  seen.clear();
  ASSERT_TRUE(ForEachDataLine(text, "a.obj", CommentStyle::kWholeLine, [&](const TextLine& line) {
                seen.push_back(std::string(line.text));
                return absl::OkStatus();
              }).ok());
  EXPECT_EQ(seen, (std::vector<std::string>{"v 1 2 # note", "f 1"}));
}

TEST(TextTokensTest, StopsAtTheFirstErrorNamingFileAndLine) {
  int calls = 0;
  const absl::Status status =
      ForEachDataLine("a\nb\nc\n", "target t", CommentStyle::kWholeLine,
                      [&](const TextLine& line) {
                        ++calls;
                        return line.text == "b" ? line.Error("bad") : absl::OkStatus();
                      });
  EXPECT_THAT(status, StatusIs(absl::StatusCode::kInvalidArgument, "target t line 2: bad: 'b'"));
  EXPECT_EQ(calls, 2);
}

}  // namespace
}  // namespace fitbase::core
