#ifndef FITBASE_STORAGE_ASSET_WRITE_H_
#define FITBASE_STORAGE_ASSET_WRITE_H_

#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace fitbase::storage {

// Changes to builds, tasks and drape results that AssetStore::Commit applies as one atomic
// RocksDB WriteBatch, so a coordinator records a task's completion, its drape result and the
// build's progress together and a crash never keeps one without the others.
//
// Ids are checked as they are added; the first invalid one is kept in status() and makes
// Commit fail without writing anything. Later changes win over earlier ones to the same record.
class AssetWrite {
 public:
  // The records a change touches; AssetStore keeps each kind in its own column family.
  enum class Kind { kBuild, kTask, kDrapeResult };
  enum class Action {
    kPut,
    kDelete,
    // Deletes every key in [key, value).
    kDeleteRange,
  };
  struct Change {
    Kind kind;
    Action action;
    std::string key;    // As encoded by EncodeKey.
    std::string value;  // kPut: the record's bytes; kDeleteRange: the end of the range.
    std::string description;  // Names the record in messages: "task 't' of build 'b'".
  };

  // Builds and tasks are mutable: a put replaces the record.
  AssetWrite& PutBuild(absl::string_view build_id, std::string bytes);
  // Deletes the build and every task of it.
  AssetWrite& DeleteBuild(absl::string_view build_id);
  AssetWrite& PutTask(absl::string_view build_id, absl::string_view task_id, std::string bytes);
  AssetWrite& DeleteTask(absl::string_view build_id, absl::string_view task_id);

  // Drape results are immutable: Commit skips a put of the bytes already stored under the key
  // (or put earlier in this write) and fails with ALREADY_EXISTS on different bytes.
  AssetWrite& PutDrapeResult(absl::string_view drape_key, std::string bytes);
  AssetWrite& DeleteDrapeResult(absl::string_view drape_key);

  const absl::Status& status() const { return status_; }
  const std::vector<Change>& changes() const { return changes_; }

 private:
  void Add(Kind kind, Action action, absl::StatusOr<std::string> key, std::string value,
           std::string description);

  absl::Status status_;
  std::vector<Change> changes_;
};

}  // namespace fitbase::storage

#endif  // FITBASE_STORAGE_ASSET_WRITE_H_
