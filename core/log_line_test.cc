#include "core/log_line.h"

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

using ::testing::EndsWith;
using ::testing::MatchesRegex;

TEST(LogLineTest, WritesEventAndFieldsInLogfmt) {
  LogLine line("task_leased");
  line.Add("build", "build-000001").Add("task", "M/007").Add("attempt", 2).Add("ms", 1.5);
  EXPECT_THAT(line.text(),
              MatchesRegex("ts=[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9:.]+Z event=task_leased "
                           "build=build-000001 task=M/007 attempt=2 ms=1.5"));
}

TEST(LogLineTest, QuotesValuesThatWouldBreakTheLine) {
  LogLine line("task_failed");
  line.Add("error", "drape of \"M\" failed: a=b\nnext").Add("empty", "");
  EXPECT_THAT(line.text(),
              EndsWith("error=\"drape of \\\"M\\\" failed: a=b\\nnext\" empty=\"\""));
}

}  // namespace
}  // namespace fitbase::core
