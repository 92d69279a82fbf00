#include "storage/record_key.h"

#include <algorithm>
#include <string>
#include <tuple>
#include <vector>

#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::storage {
namespace {

using core::StatusIs;
using ::testing::ElementsAre;

TEST(RecordKeyTest, RoundTrip) {
  auto key = EncodeKey({{"tenant", "acme"}, {"garment_id", "shirt-01"}});
  ASSERT_TRUE(key.ok()) << key.status();
  EXPECT_EQ(*key, std::string("acme\0shirt-01\0", 14));
  auto ids = DecodeKey(*key);
  ASSERT_TRUE(ids.ok()) << ids.status();
  EXPECT_THAT(*ids, ElementsAre("acme", "shirt-01"));
}

TEST(RecordKeyTest, KeysSortLikeTuplesOfIds) {
  // "a" < "a!" < "ab" as ids, though "a" + terminator + "z" would sort after "a!" if the
  // terminator were any id byte.
  const std::vector<std::pair<std::string, std::string>> tuples = {
      {"ab", "a"}, {"a", "z"}, {"a!", "a"}, {"a", "b"}, {"~", "~"}, {"a", "a"}, {"!", "~"}};
  std::vector<std::pair<std::string, std::string>> by_tuple = tuples;
  std::sort(by_tuple.begin(), by_tuple.end());
  std::vector<std::pair<std::string, std::pair<std::string, std::string>>> by_key;
  for (const auto& [first, second] : tuples) {
    auto key = EncodeKey({{"first", first}, {"second", second}});
    ASSERT_TRUE(key.ok()) << key.status();
    by_key.push_back({*key, {first, second}});
  }
  std::sort(by_key.begin(), by_key.end());
  for (size_t i = 0; i < tuples.size(); ++i) EXPECT_EQ(by_key[i].second, by_tuple[i]) << i;
}

TEST(RecordKeyTest, ParentKeyIsPrefixOfExactlyItsChildren) {
  const std::string tenant = *EncodeKey({{"tenant", "ab"}});
  EXPECT_TRUE(EncodeKey({{"tenant", "ab"}, {"garment_id", "g"}})->starts_with(tenant));
  EXPECT_FALSE(EncodeKey({{"tenant", "abc"}, {"garment_id", "g"}})->starts_with(tenant));
  EXPECT_FALSE(EncodeKey({{"tenant", "a"}, {"garment_id", "bg"}})->starts_with(tenant));
}

TEST(RecordKeyTest, InvalidIdsNameTheirField) {
  EXPECT_THAT(EncodeKey({{"tenant", "t"}, {"garment_id", ""}}),
              StatusIs(absl::StatusCode::kInvalidArgument, "garment_id is empty"));
  EXPECT_THAT(EncodeKey({{"tenant", "has space"}}),
              StatusIs(absl::StatusCode::kInvalidArgument, "tenant has byte 0x20 at offset 3"));
  EXPECT_THAT(EncodeKey({{"size", std::string("M\0", 2)}}),
              StatusIs(absl::StatusCode::kInvalidArgument, "size has byte 0x00 at offset 1"));
  EXPECT_THAT(EncodeKey({{"method", "caf\xc3\xa9"}}),
              StatusIs(absl::StatusCode::kInvalidArgument, "method has byte 0xC3 at offset 3"));
  EXPECT_THAT(EncodeKey({{"build_id", "a\nb"}}),
              StatusIs(absl::StatusCode::kInvalidArgument, "build_id has byte 0x0A"));
  EXPECT_THAT(ValidateId("task_id", std::string(kMaxIdBytes + 1, 'x')),
              StatusIs(absl::StatusCode::kInvalidArgument, "task_id is 257 bytes, more than 256"));
  EXPECT_TRUE(ValidateId("task_id", std::string(kMaxIdBytes, 'x')).ok());
  EXPECT_TRUE(ValidateId("task_id", "!~").ok());
}

TEST(RecordKeyTest, MalformedStoredKeysAreDataLoss) {
  EXPECT_THAT(DecodeKey("abc"), StatusIs(absl::StatusCode::kDataLoss, "unterminated"));
  EXPECT_THAT(DecodeKey(std::string("a\0\0", 3)),
              StatusIs(absl::StatusCode::kDataLoss, "stored key's id 1 is empty"));
  auto empty = DecodeKey("");
  ASSERT_TRUE(empty.ok());
  EXPECT_TRUE(empty->empty());
}

TEST(RecordKeyTest, VersionsSortNumerically) {
  std::vector<uint64_t> versions = {256, 1, 255, 65536, 2, uint64_t{1} << 63, 0xFFFFFFFF};
  std::vector<std::string> encoded;
  for (uint64_t v : versions) encoded.push_back(EncodeVersion(v));
  std::sort(versions.begin(), versions.end());
  std::sort(encoded.begin(), encoded.end());
  for (size_t i = 0; i < versions.size(); ++i) {
    EXPECT_EQ(encoded[i].size(), 8u);
    auto decoded = DecodeVersion(encoded[i]);
    ASSERT_TRUE(decoded.ok()) << decoded.status();
    EXPECT_EQ(*decoded, versions[i]);
  }
  EXPECT_EQ(EncodeVersion(0x0102), std::string("\0\0\0\0\0\0\x01\x02", 8));
  EXPECT_THAT(DecodeVersion("1234567"), StatusIs(absl::StatusCode::kDataLoss, "7 bytes, not 8"));
}

TEST(RecordKeyTest, ClothingBasisKeyEncodesFieldsInOrder) {
  const ClothingBasisKey key{"acme", "shirt", "M", "basis", "linear"};
  auto encoded = EncodeClothingBasisKey(key);
  ASSERT_TRUE(encoded.ok()) << encoded.status();
  EXPECT_THAT(*DecodeKey(*encoded), ElementsAre("acme", "shirt", "M", "basis", "linear"));
  ClothingBasisKey bad = key;
  bad.avatar_basis_id = "";
  EXPECT_THAT(EncodeClothingBasisKey(bad),
              StatusIs(absl::StatusCode::kInvalidArgument, "avatar_basis_id is empty"));
  EXPECT_EQ(DescribeClothingBasisKey(key),
            "clothing basis (tenant 'acme', garment 'shirt', size 'M', avatar basis 'basis', "
            "method 'linear')");
}

}  // namespace
}  // namespace fitbase::storage
