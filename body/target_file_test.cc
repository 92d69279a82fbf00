#include "body/target_file.h"

#include "core/test_support.h"
#include "gtest/gtest.h"

namespace fitbase::body {
namespace {

TEST(TargetFileTest, ParsesCommentsBlankLinesAndOffsets) {
  auto target = ParseTarget("# header\n\n3 .5 -1 0.25\n  0 0 0 -.125  \r\n", 10, "t");
  ASSERT_TRUE(target.ok()) << target.status();
  ASSERT_EQ(target->indices, (std::vector<int32_t>{3, 0}));
  EXPECT_EQ(target->offsets(0, 0), 0.5);
  EXPECT_EQ(target->offsets(0, 1), -1.0);
  EXPECT_EQ(target->offsets(1, 2), -0.125);
}

TEST(TargetFileTest, EmptyTargetIsIdentity) {
  auto target = ParseTarget("# nothing moves\n", 10, "t");
  ASSERT_TRUE(target.ok());
  EXPECT_TRUE(target->indices.empty());
  EXPECT_EQ(target->offsets.rows(), 0);
}

TEST(TargetFileTest, MalformedLinesNameFileAndLine) {
  struct Case {
    const char* text;
    const char* expected;
  };
  for (const Case& c : {Case{"1 2 3\n", "expected 'index dx dy dz'"},
                        Case{"1 2 3 4 5\n", "expected 'index dx dy dz'"},
                        Case{"x 0 0 0\n", "not an integer"},
                        Case{"1.5 0 0 0\n", "not an integer"},
                        Case{"10 0 0 0\n", "outside [0, 10)"},
                        Case{"-1 0 0 0\n", "outside [0, 10)"},
                        Case{"1 0 nan 0\n", "finite"},
                        Case{"1 0 inf 0\n", "finite"},
                        Case{"1 0 0 0\n1 1 1 1\n", "repeated"}}) {
    auto target = ParseTarget(std::string("# c\n") + c.text, 10, "bad.target");
    ASSERT_FALSE(target.ok()) << c.text;
    EXPECT_EQ(target.status().code(), absl::StatusCode::kInvalidArgument);
    EXPECT_NE(target.status().message().find(c.expected), absl::string_view::npos)
        << target.status();
    EXPECT_NE(target.status().message().find("target bad.target line "), absl::string_view::npos);
  }
}

TEST(TargetFileTest, ReadsShippedTarget) {
  auto target = ReadTargetFile(
      core::TestDataDir() / "targets/measure/measure-waist-circ-incr.target", 19158);
  ASSERT_TRUE(target.ok()) << target.status();
  EXPECT_GT(target->indices.size(), 100u);
}

TEST(TargetFileTest, MissingFileIsNotFound) {
  auto target = ReadTargetFile(core::TestDataDir() / "targets/no-such.target", 19158);
  EXPECT_EQ(target.status().code(), absl::StatusCode::kNotFound);
}

}  // namespace
}  // namespace fitbase::body
