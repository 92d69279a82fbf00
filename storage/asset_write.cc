#include "storage/asset_write.h"

#include <utility>

#include "absl/strings/str_cat.h"
#include "storage/record_key.h"

namespace fitbase::storage {
namespace {

std::string BuildName(absl::string_view build_id) {
  return absl::StrCat("build '", build_id, "'");
}

std::string TaskName(absl::string_view build_id, absl::string_view task_id) {
  return absl::StrCat("task '", task_id, "' of build '", build_id, "'");
}

std::string DrapeResultName(absl::string_view drape_key) {
  return absl::StrCat("drape result '", drape_key, "'");
}

}  // namespace

void AssetWrite::Add(Kind kind, Action action, absl::StatusOr<std::string> key,
                     std::string value, std::string description) {
  if (!status_.ok()) return;
  if (!key.ok()) {
    status_ = key.status();
    return;
  }
  changes_.push_back(
      {kind, action, *std::move(key), std::move(value), std::move(description)});
}

AssetWrite& AssetWrite::PutBuild(absl::string_view build_id, std::string bytes) {
  Add(Kind::kBuild, Action::kPut, EncodeKey({{"build_id", build_id}}), std::move(bytes),
      BuildName(build_id));
  return *this;
}

AssetWrite& AssetWrite::DeleteBuild(absl::string_view build_id) {
  absl::StatusOr<std::string> key = EncodeKey({{"build_id", build_id}});
  Add(Kind::kBuild, Action::kDelete, key, "", BuildName(build_id));
  if (!key.ok()) return *this;
  // The build's task keys all start with its key, which ends in kIdTerminator ('\0'); the
  // same key ending in '\1' is the first key after all of them and before any other build's.
  std::string end = *key;
  end.back() = '\1';
  Add(Kind::kTask, Action::kDeleteRange, key, std::move(end),
      absl::StrCat("tasks of ", BuildName(build_id)));
  return *this;
}

AssetWrite& AssetWrite::PutTask(absl::string_view build_id, absl::string_view task_id,
                                std::string bytes) {
  Add(Kind::kTask, Action::kPut, EncodeKey({{"build_id", build_id}, {"task_id", task_id}}),
      std::move(bytes), TaskName(build_id, task_id));
  return *this;
}

AssetWrite& AssetWrite::DeleteTask(absl::string_view build_id, absl::string_view task_id) {
  Add(Kind::kTask, Action::kDelete, EncodeKey({{"build_id", build_id}, {"task_id", task_id}}),
      "", TaskName(build_id, task_id));
  return *this;
}

AssetWrite& AssetWrite::PutDrapeResult(absl::string_view drape_key, std::string bytes) {
  Add(Kind::kDrapeResult, Action::kPut, EncodeKey({{"drape_key", drape_key}}),
      std::move(bytes), DrapeResultName(drape_key));
  return *this;
}

AssetWrite& AssetWrite::DeleteDrapeResult(absl::string_view drape_key) {
  Add(Kind::kDrapeResult, Action::kDelete, EncodeKey({{"drape_key", drape_key}}), "",
      DrapeResultName(drape_key));
  return *this;
}

}  // namespace fitbase::storage
