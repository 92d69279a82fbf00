#include "core/file_util.h"

#include "core/test_support.h"
#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

TEST(FileUtilTest, AtomicWriteReplacesWholeFile) {
  const auto path = ProcessTempDir() / "atomic.bin";
  ASSERT_TRUE(WriteFileAtomically(path, std::string("first version, longer")).ok());
  ASSERT_TRUE(WriteFileAtomically(path, std::string("second\0bytes", 12)).ok());
  auto bytes = ReadFileToString(path);
  ASSERT_TRUE(bytes.ok());
  EXPECT_EQ(*bytes, std::string("second\0bytes", 12));
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
}

TEST(FileUtilTest, ErrorsAreStatuses) {
  EXPECT_EQ(ReadFileToString("/nonexistent/file").status().code(), absl::StatusCode::kNotFound);
  EXPECT_FALSE(WriteFileAtomically("/nonexistent/dir/file", "x").ok());
}

}  // namespace
}  // namespace fitbase::core
