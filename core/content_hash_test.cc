#include "core/content_hash.h"

#include <vector>

#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

TEST(ContentHashTest, KnownDigestOfLengthPrefixedField) {
  // SHA-256 of the 8-byte little-endian length 0 (one empty field).
  EXPECT_EQ(ContentHash().Add(absl::string_view()).HexDigest(),
            "af5570f5a1810b7af78caf4bc70a660f0df51e42baf91d4de5b2328de0e83dfc");
}

TEST(ContentHashTest, FieldBoundariesMatter) {
  EXPECT_NE(ContentHash().Add("ab").Add("c").HexDigest(),
            ContentHash().Add("a").Add("bc").HexDigest());
}

TEST(ContentHashTest, SameInputSameDigest) {
  const std::vector<float> values = {1.0f, -2.5f, 3.25f};
  auto digest = [&] {
    return ContentHash().Add("x").Add(values).Add(2.0).Add(int64_t{7}).HexDigest();
  };
  EXPECT_EQ(digest(), digest());
  EXPECT_EQ(digest().size(), 64u);
  EXPECT_NE(digest(), ContentHash().Add("x").Add(values).Add(2.0).Add(int64_t{8}).HexDigest());
}

TEST(Sha256HexTest, KnownDigests) {
  // FIPS 180-2 test vectors.
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

}  // namespace
}  // namespace fitbase::core
