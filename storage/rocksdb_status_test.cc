#include "storage/rocksdb_status.h"

#include <utility>
#include <vector>

#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::storage {
namespace {

using core::StatusIs;

TEST(RocksDbStatusTest, OkIsOk) {
  EXPECT_TRUE(FromRocksDbStatus(rocksdb::Status::OK(), "x").ok());
}

TEST(RocksDbStatusTest, MessageNamesContextAndCause) {
  EXPECT_THAT(FromRocksDbStatus(rocksdb::Status::Corruption("bad block"), "get garment 'g'"),
              StatusIs(absl::StatusCode::kDataLoss, "get garment 'g': Corruption: bad block"));
}

TEST(RocksDbStatusTest, CodesSayWhatTheCallerCanDo) {
  const std::vector<std::pair<rocksdb::Status, absl::StatusCode>> cases = {
      {rocksdb::Status::NotFound(), absl::StatusCode::kNotFound},
      {rocksdb::Status::Corruption(), absl::StatusCode::kDataLoss},
      {rocksdb::Status::NotSupported(), absl::StatusCode::kUnimplemented},
      {rocksdb::Status::InvalidArgument(), absl::StatusCode::kInvalidArgument},
      {rocksdb::Status::IOError("disk"), absl::StatusCode::kUnavailable},
      {rocksdb::Status::NoSpace(), absl::StatusCode::kResourceExhausted},
      {rocksdb::Status::IOError(rocksdb::Status::kSpaceLimit),
       absl::StatusCode::kResourceExhausted},
      {rocksdb::Status::PathNotFound(), absl::StatusCode::kNotFound},
      {rocksdb::Status::Busy(), absl::StatusCode::kUnavailable},
      {rocksdb::Status::TryAgain(), absl::StatusCode::kUnavailable},
      {rocksdb::Status::ShutdownInProgress(), absl::StatusCode::kUnavailable},
      {rocksdb::Status::Incomplete(), absl::StatusCode::kUnavailable},
      {rocksdb::Status::TimedOut(), absl::StatusCode::kDeadlineExceeded},
      {rocksdb::Status::Aborted(), absl::StatusCode::kAborted},
      {rocksdb::Status::MemoryLimit(), absl::StatusCode::kResourceExhausted},
      {rocksdb::Status::ColumnFamilyDropped(), absl::StatusCode::kFailedPrecondition},
      {rocksdb::Status::MergeInProgress(), absl::StatusCode::kInternal},
  };
  for (const auto& [status, code] : cases) {
    EXPECT_EQ(FromRocksDbStatus(status, "op").code(), code) << status.ToString();
  }
}

}  // namespace
}  // namespace fitbase::storage
