#ifndef FITBASE_STORAGE_ROCKSDB_STATUS_H_
#define FITBASE_STORAGE_ROCKSDB_STATUS_H_

#include "absl/status/status.h"
#include "absl/strings/string_view.h"
#include "rocksdb/status.h"

namespace fitbase::storage {

// The absl::Status of a RocksDB result, with the message "<context>: <RocksDB's message>";
// `context` names the operation and the record ("get garment 'g' of tenant 't'"). Codes say
// what a caller can do: NotFound is NOT_FOUND, Corruption DATA_LOSS, a full disk
// RESOURCE_EXHAUSTED, a missing path NOT_FOUND, other I/O errors, busy and shutdown
// UNAVAILABLE (retrying may succeed), InvalidArgument INVALID_ARGUMENT, NotSupported
// UNIMPLEMENTED; anything unexpected is INTERNAL.
absl::Status FromRocksDbStatus(const rocksdb::Status& status, absl::string_view context);

}  // namespace fitbase::storage

#endif  // FITBASE_STORAGE_ROCKSDB_STATUS_H_
