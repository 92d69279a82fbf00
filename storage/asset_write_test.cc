#include "storage/asset_write.h"

#include <string>

#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "storage/record_key.h"

namespace fitbase::storage {
namespace {

using core::StatusIs;

TEST(AssetWriteTest, RecordsChangesInOrderWithEncodedKeys) {
  AssetWrite write;
  write.PutTask("b1", "t1", "done").PutDrapeResult("d1", "drape").PutBuild("b1", "running");
  ASSERT_TRUE(write.status().ok()) << write.status();
  ASSERT_EQ(write.changes().size(), 3u);
  const AssetWrite::Change& task = write.changes()[0];
  EXPECT_EQ(task.kind, AssetWrite::Kind::kTask);
  EXPECT_EQ(task.action, AssetWrite::Action::kPut);
  EXPECT_EQ(task.key, *EncodeKey({{"build_id", "b1"}, {"task_id", "t1"}}));
  EXPECT_EQ(task.value, "done");
  EXPECT_EQ(task.description, "task 't1' of build 'b1'");
  EXPECT_EQ(write.changes()[1].kind, AssetWrite::Kind::kDrapeResult);
  EXPECT_EQ(write.changes()[1].key, *EncodeKey({{"drape_key", "d1"}}));
  EXPECT_EQ(write.changes()[2].kind, AssetWrite::Kind::kBuild);
  EXPECT_EQ(write.changes()[2].value, "running");
}

TEST(AssetWriteTest, FirstInvalidIdIsKeptAndNothingAfterIt) {
  AssetWrite write;
  write.PutBuild("b1", "x").PutTask("b1", "bad id", "x").PutDrapeResult("", "x");
  EXPECT_THAT(write.status(), StatusIs(absl::StatusCode::kInvalidArgument, "task_id has byte"));
  EXPECT_EQ(write.changes().size(), 1u);
}

TEST(AssetWriteTest, DeleteBuildCoversExactlyItsTasks) {
  AssetWrite write;
  write.DeleteBuild("b");
  ASSERT_TRUE(write.status().ok()) << write.status();
  ASSERT_EQ(write.changes().size(), 2u);
  EXPECT_EQ(write.changes()[0].kind, AssetWrite::Kind::kBuild);
  EXPECT_EQ(write.changes()[0].action, AssetWrite::Action::kDelete);
  const AssetWrite::Change& range = write.changes()[1];
  EXPECT_EQ(range.kind, AssetWrite::Kind::kTask);
  ASSERT_EQ(range.action, AssetWrite::Action::kDeleteRange);
  auto in_range = [&](absl::string_view build_id, absl::string_view task_id) {
    const std::string key = *EncodeKey({{"build_id", build_id}, {"task_id", task_id}});
    return range.key <= key && key < range.value;
  };
  EXPECT_TRUE(in_range("b", "!"));
  EXPECT_TRUE(in_range("b", std::string(kMaxIdBytes, '~')));
  EXPECT_FALSE(in_range("a", "~"));
  EXPECT_FALSE(in_range("b!", "!"));
  EXPECT_FALSE(in_range("ba", "x"));
}

}  // namespace
}  // namespace fitbase::storage
