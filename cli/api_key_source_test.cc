#include "cli/api_key_source.h"

#include <stdlib.h>

#include <fstream>

#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::cli {
namespace {

using ::fitbase::core::StatusIs;
using ::testing::HasSubstr;
using ::testing::Not;

TEST(ApiKeySourceTest, ReadsTheEnvironmentTrimmed) {
  ASSERT_EQ(setenv(kApiKeyVariable, " fb_0123abc\n", 1), 0);
  absl::StatusOr<std::string> key = ApiKeyFromEnvironment();
  ASSERT_TRUE(key.ok()) << key.status();
  EXPECT_EQ(*key, "fb_0123abc");

  ASSERT_EQ(setenv(kApiKeyVariable, "  ", 1), 0);
  EXPECT_THAT(ApiKeyFromEnvironment(),
              StatusIs(absl::StatusCode::kFailedPrecondition, "FITBASE_API_KEY holds no API key"));
  ASSERT_EQ(unsetenv(kApiKeyVariable), 0);
  EXPECT_THAT(ApiKeyFromEnvironment(),
              StatusIs(absl::StatusCode::kFailedPrecondition, "FITBASE_API_KEY is not set"));
}

TEST(ApiKeySourceTest, ReadsTheFirstLineOfAFile) {
  const std::filesystem::path path = core::ProcessTempDir() / "key";
  std::ofstream(path) << "fb_0123abc  \r\nsecond line\n";
  absl::StatusOr<std::string> key = ApiKeyFromFile(path);
  ASSERT_TRUE(key.ok()) << key.status();
  EXPECT_EQ(*key, "fb_0123abc");
  EXPECT_THAT(ApiKeyFromFile(core::ProcessTempDir() / "absent"),
              StatusIs(absl::StatusCode::kNotFound, "absent"));
}

TEST(ApiKeySourceTest, RefusesBytesMetadataCannotCarryWithoutEchoingTheKey) {
  const std::filesystem::path path = core::ProcessTempDir() / "bad-key";
  std::ofstream(path) << "fb_secret part\n";
  absl::StatusOr<std::string> key = ApiKeyFromFile(path);
  EXPECT_THAT(key, StatusIs(absl::StatusCode::kFailedPrecondition, "byte 0x20 at offset 9"));
  EXPECT_THAT(std::string(key.status().message()), Not(HasSubstr("secret")));
}

}  // namespace
}  // namespace fitbase::cli
