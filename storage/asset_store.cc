#include "storage/asset_store.h"

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "rocksdb/convenience.h"
#include "rocksdb/db.h"
#include "rocksdb/options.h"
#include "rocksdb/snapshot.h"
#include "rocksdb/utilities/checkpoint.h"
#include "rocksdb/utilities/options_util.h"
#include "rocksdb/write_batch.h"
#include "storage/rocksdb_status.h"

namespace fitbase::storage {
namespace {

// Debian's Abseil has its own string_view, which RocksDB's Slice does not take.
rocksdb::Slice ToSlice(absl::string_view bytes) { return {bytes.data(), bytes.size()}; }
absl::string_view ToStringView(const rocksdb::Slice& slice) {
  return {slice.data(), slice.size()};
}

std::string AvatarBasisName(absl::string_view avatar_basis_id) {
  return absl::StrCat("avatar basis '", avatar_basis_id, "'");
}

std::string CurrentAvatarBasisName(absl::string_view tenant, absl::string_view population) {
  return absl::StrCat("current avatar basis of population '", population, "' of tenant '",
                      tenant, "'");
}

std::string GarmentName(absl::string_view tenant, absl::string_view garment_id) {
  return absl::StrCat("garment '", garment_id, "' of tenant '", tenant, "'");
}

// Whether an immutable record must be written, given what is `stored` under its key: not when
// it holds the same bytes; ALREADY_EXISTS when it holds others.
absl::StatusOr<bool> IsNewRecord(std::optional<absl::string_view> stored,
                                 absl::string_view bytes, absl::string_view what) {
  if (!stored.has_value()) return true;
  if (*stored == bytes) return false;
  return absl::AlreadyExistsError(absl::StrCat(what, " is stored with other bytes (",
                                               stored->size(), " stored, ", bytes.size(),
                                               " given); records are immutable"));
}

// Whether the database at `path` keeps large values in blob files, as its latest OPTIONS file
// says; nullopt when there is no database there yet.
absl::StatusOr<std::optional<bool>> StoredBlobFiles(const std::filesystem::path& path,
                                                    absl::string_view what) {
  rocksdb::DBOptions db_options;
  std::vector<rocksdb::ColumnFamilyDescriptor> descriptors;
  const rocksdb::Status status =
      rocksdb::LoadLatestOptions(rocksdb::ConfigOptions(), path.string(), &db_options,
                                 &descriptors);
  if (status.IsNotFound() || status.IsPathNotFound()) return std::nullopt;
  RETURN_IF_ERROR(FromRocksDbStatus(status, absl::StrCat(what, ": read its options")));
  bool blob_files = false;
  for (const rocksdb::ColumnFamilyDescriptor& descriptor : descriptors) {
    blob_files = blob_files || descriptor.options.enable_blob_files;
  }
  return blob_files;
}

}  // namespace

// The state that reads of one operation share: a snapshot on a primary (writers may commit
// between the reads); on a secondary, catch-up held off; a read-only database never changes.
class AssetStore::ReadView {
 public:
  explicit ReadView(const AssetStore& store) : lock_(store.catch_up_mutex_) {
    if (store.options_.mode == OpenMode::kPrimary) {
      snapshot_.emplace(store.db_.get());
      options_.snapshot = snapshot_->snapshot();
    }
  }

  const rocksdb::ReadOptions& options() const { return options_; }

 private:
  std::shared_lock<std::shared_mutex> lock_;
  std::optional<rocksdb::ManagedSnapshot> snapshot_;
  rocksdb::ReadOptions options_;
};

absl::StatusOr<std::unique_ptr<AssetStore>> AssetStore::Open(const std::filesystem::path& path,
                                                             const OpenOptions& options) {
  static constexpr const char* kColumnNames[] = {
      "default",        "avatar_bases",      "avatar_current", "garments", "garment_ids",
      "clothing_bases", "clothing_versions", "drape_results",  "builds",   "tasks"};
  static_assert(std::size(kColumnNames) == kColumnCount);

  rocksdb::DBOptions db_options;
  db_options.create_if_missing = options.mode == OpenMode::kPrimary;
  db_options.create_missing_column_families = options.mode == OpenMode::kPrimary;
  // A WAL file is deleted only once every column family with writes in it has flushed; this
  // cap makes RocksDB flush the rarely written ones (pointers, indexes) instead of keeping
  // WAL files forever.
  db_options.max_total_wal_size = uint64_t{512} << 20;
  // Required by OpenAsSecondary: the secondary keeps every table file open, so the primary's
  // compactions cannot delete one from under a read.
  if (options.mode == OpenMode::kSecondary) db_options.max_open_files = -1;

  std::vector<rocksdb::ColumnFamilyDescriptor> descriptors;
  for (int column = 0; column < kColumnCount; ++column) {
    rocksdb::ColumnFamilyOptions column_options;
    if (options.blob_files && (column == kAvatarBases || column == kGarments ||
                               column == kClothingBases || column == kDrapeResults)) {
      column_options.enable_blob_files = true;
      column_options.min_blob_size = options.min_blob_bytes;
      // Blobs of deleted records are reclaimed when compaction rewrites old blob files.
      column_options.enable_blob_garbage_collection = true;
    }
    descriptors.emplace_back(kColumnNames[column], column_options);
  }

  const char* const mode_names[] = {"primary", "read-only", "secondary"};
  const std::string what = absl::StrCat("open asset store ", path.string(), " (",
                                        mode_names[static_cast<int>(options.mode)], ")");
  if (options.mode == OpenMode::kSecondary && options.secondary_path.empty()) {
    return absl::InvalidArgumentError(absl::StrCat(what, ": secondary_path is empty"));
  }
  if (options.mode != OpenMode::kReadOnly) {
    ASSIGN_OR_RETURN(const std::optional<bool> blob_files, StoredBlobFiles(path, what));
    if (blob_files.has_value() && options.mode == OpenMode::kPrimary &&
        *blob_files != options.blob_files) {
      return absl::FailedPreconditionError(
          absl::StrCat(what, ": the database was created with blob_files = ",
                       *blob_files ? "true" : "false", ", which is fixed at creation"));
    }
    if (blob_files.value_or(false) && options.mode == OpenMode::kSecondary) {
      return absl::FailedPreconditionError(absl::StrCat(
          what, ": the database keeps large values in blob files, which RocksDB secondaries "
                "cannot read (facebook/rocksdb#13296); open a checkpoint read-only instead"));
    }
  }

  std::vector<rocksdb::ColumnFamilyHandle*> handles;
  rocksdb::DB* db = nullptr;
  rocksdb::Status status;
  switch (options.mode) {
    case OpenMode::kPrimary:
      status = rocksdb::DB::Open(db_options, path.string(), descriptors, &handles, &db);
      break;
    case OpenMode::kReadOnly:
      status =
          rocksdb::DB::OpenForReadOnly(db_options, path.string(), descriptors, &handles, &db);
      break;
    case OpenMode::kSecondary:
      status = rocksdb::DB::OpenAsSecondary(db_options, path.string(),
                                            options.secondary_path.string(), descriptors,
                                            &handles, &db);
      break;
  }
  RETURN_IF_ERROR(FromRocksDbStatus(status, what));
  return std::unique_ptr<AssetStore>(
      new AssetStore(std::unique_ptr<rocksdb::DB>(db), std::move(handles), options));
}

AssetStore::AssetStore(std::unique_ptr<rocksdb::DB> db,
                       std::vector<rocksdb::ColumnFamilyHandle*> handles,
                       const OpenOptions& options)
    : db_(std::move(db)), handles_(std::move(handles)), options_(options) {}

AssetStore::~AssetStore() {
  // Failures here concern a database being let go, with no caller left to tell: every write
  // that was acknowledged is already in the WAL.
  for (rocksdb::ColumnFamilyHandle* handle : handles_) {
    db_->DestroyColumnFamilyHandle(handle).PermitUncheckedError();
  }
  db_->Close().PermitUncheckedError();
}

absl::Status AssetStore::CheckWritable(absl::string_view what) const {
  if (options_.mode == OpenMode::kPrimary) return absl::OkStatus();
  return absl::FailedPreconditionError(
      absl::StrCat(what, ": the asset store is open ",
                   options_.mode == OpenMode::kReadOnly ? "read-only" : "as a secondary",
                   "; only the primary writes"));
}

absl::Status AssetStore::CheckValueSize(absl::string_view bytes, absl::string_view what) const {
  if (bytes.size() <= options_.max_value_bytes) return absl::OkStatus();
  return absl::ResourceExhaustedError(absl::StrCat(what, " is ", bytes.size(),
                                                   " bytes, more than the limit of ",
                                                   options_.max_value_bytes));
}

absl::StatusOr<std::optional<std::string>> AssetStore::Read(const ReadView& view, Column column,
                                                            absl::string_view key,
                                                            absl::string_view what) const {
  std::string value;
  const rocksdb::Status status = db_->Get(view.options(), handles_[column], ToSlice(key), &value);
  if (status.IsNotFound()) return std::nullopt;
  RETURN_IF_ERROR(FromRocksDbStatus(status, absl::StrCat("read ", what)));
  return value;
}

absl::StatusOr<std::string> AssetStore::ReadExisting(const ReadView& view, Column column,
                                                     absl::string_view key,
                                                     absl::string_view what) const {
  ASSIGN_OR_RETURN(std::optional<std::string> value, Read(view, column, key, what));
  if (!value.has_value()) return absl::NotFoundError(absl::StrCat(what, " not found"));
  return *std::move(value);
}

absl::StatusOr<std::optional<AssetStore::LogEntry>> AssetStore::Newest(
    const ReadView& view, Column column, absl::string_view prefix, absl::string_view what) const {
  const std::string last = absl::StrCat(prefix, EncodeVersion(UINT64_MAX));
  std::unique_ptr<rocksdb::Iterator> it(db_->NewIterator(view.options(), handles_[column]));
  it->SeekForPrev(last);
  if (!it->Valid() || !it->key().starts_with(ToSlice(prefix))) {
    RETURN_IF_ERROR(FromRocksDbStatus(it->status(), absl::StrCat("read ", what)));
    return std::nullopt;
  }
  absl::string_view number = ToStringView(it->key());
  number.remove_prefix(prefix.size());
  LogEntry entry;
  ASSIGN_OR_RETURN(entry.number, DecodeVersion(number));
  entry.value = it->value().ToString();
  return entry;
}

absl::Status AssetStore::Scan(
    const ReadView& view, Column column, absl::string_view prefix, absl::string_view what,
    absl::FunctionRef<absl::Status(absl::string_view rest, absl::string_view value)> visit)
    const {
  std::unique_ptr<rocksdb::Iterator> it(db_->NewIterator(view.options(), handles_[column]));
  for (it->Seek(ToSlice(prefix)); it->Valid() && it->key().starts_with(ToSlice(prefix));
       it->Next()) {
    absl::string_view rest = ToStringView(it->key());
    rest.remove_prefix(prefix.size());
    RETURN_IF_ERROR(visit(rest, ToStringView(it->value())));
  }
  return FromRocksDbStatus(it->status(), absl::StrCat("list ", what));
}

absl::StatusOr<std::vector<JobRecord>> AssetStore::ListRecords(Column column,
                                                               absl::string_view prefix,
                                                               absl::string_view what) const {
  const ReadView view(*this);
  std::vector<JobRecord> records;
  RETURN_IF_ERROR(Scan(view, column, prefix, what,
                       [&](absl::string_view rest, absl::string_view value) -> absl::Status {
                         ASSIGN_OR_RETURN(std::vector<std::string> ids, DecodeKey(rest));
                         if (ids.size() != 1) {
                           return absl::DataLossError(absl::StrCat(
                               "list ", what, ": stored key has ", ids.size(), " ids, not 1"));
                         }
                         records.push_back({std::move(ids[0]), std::string(value)});
                         return absl::OkStatus();
                       }));
  return records;
}

absl::Status AssetStore::Write(rocksdb::WriteBatch* batch, bool sync, absl::string_view what) {
  rocksdb::WriteOptions write_options;
  write_options.sync = sync;
  return FromRocksDbStatus(db_->Write(write_options, batch), what);
}

absl::Status AssetStore::PutImmutable(Column column, absl::string_view key,
                                      absl::string_view bytes, Column index_column,
                                      absl::string_view what) {
  RETURN_IF_ERROR(CheckWritable(absl::StrCat("put ", what)));
  RETURN_IF_ERROR(CheckValueSize(bytes, what));
  std::lock_guard<std::mutex> lock(write_mutex_);
  const ReadView view(*this);
  ASSIGN_OR_RETURN(std::optional<std::string> stored, Read(view, column, key, what));
  ASSIGN_OR_RETURN(const bool is_new, IsNewRecord(stored, bytes, what));
  if (!is_new) return absl::OkStatus();
  rocksdb::WriteBatch batch;
  RETURN_IF_ERROR(
      FromRocksDbStatus(batch.Put(handles_[column], ToSlice(key), ToSlice(bytes)), what));
  if (index_column != kDefault) {
    RETURN_IF_ERROR(FromRocksDbStatus(batch.Put(handles_[index_column], ToSlice(key), ""), what));
  }
  return Write(&batch, /*sync=*/true, absl::StrCat("put ", what));
}

absl::Status AssetStore::PutAvatarBasis(absl::string_view avatar_basis_id,
                                        absl::string_view bytes) {
  ASSIGN_OR_RETURN(const std::string key, EncodeKey({{"avatar_basis_id", avatar_basis_id}}));
  return PutImmutable(kAvatarBases, key, bytes, kDefault, AvatarBasisName(avatar_basis_id));
}

absl::StatusOr<std::string> AssetStore::GetAvatarBasis(absl::string_view avatar_basis_id) const {
  ASSIGN_OR_RETURN(const std::string key, EncodeKey({{"avatar_basis_id", avatar_basis_id}}));
  return ReadExisting(ReadView(*this), kAvatarBases, key, AvatarBasisName(avatar_basis_id));
}

absl::Status AssetStore::PublishAvatarBasis(absl::string_view tenant,
                                            absl::string_view population,
                                            absl::string_view avatar_basis_id,
                                            absl::string_view bytes) {
  ASSIGN_OR_RETURN(const std::string pointer_prefix,
                   EncodeKey({{"tenant", tenant}, {"population", population}}));
  ASSIGN_OR_RETURN(const std::string basis_key,
                   EncodeKey({{"avatar_basis_id", avatar_basis_id}}));
  const std::string basis_name = AvatarBasisName(avatar_basis_id);
  const std::string pointer_name = CurrentAvatarBasisName(tenant, population);
  const std::string what = absl::StrCat("publish ", basis_name, " as ", pointer_name);
  RETURN_IF_ERROR(CheckWritable(what));
  RETURN_IF_ERROR(CheckValueSize(bytes, basis_name));
  std::lock_guard<std::mutex> lock(write_mutex_);
  const ReadView view(*this);
  ASSIGN_OR_RETURN(std::optional<std::string> stored,
                   Read(view, kAvatarBases, basis_key, basis_name));
  ASSIGN_OR_RETURN(const bool is_new, IsNewRecord(stored, bytes, basis_name));
  ASSIGN_OR_RETURN(std::optional<LogEntry> current,
                   Newest(view, kAvatarCurrent, pointer_prefix, pointer_name));
  rocksdb::WriteBatch batch;
  if (is_new) {
    RETURN_IF_ERROR(FromRocksDbStatus(
        batch.Put(handles_[kAvatarBases], ToSlice(basis_key), ToSlice(bytes)), what));
  }
  if (!current.has_value() || current->value != avatar_basis_id) {
    const uint64_t number = current.has_value() ? current->number + 1 : 1;
    RETURN_IF_ERROR(FromRocksDbStatus(
        batch.Put(handles_[kAvatarCurrent],
                  absl::StrCat(pointer_prefix, EncodeVersion(number)), ToSlice(avatar_basis_id)),
        what));
  }
  if (batch.Count() == 0) return absl::OkStatus();
  return Write(&batch, /*sync=*/true, what);
}

absl::StatusOr<std::string> AssetStore::GetCurrentAvatarBasisId(
    absl::string_view tenant, absl::string_view population) const {
  ASSIGN_OR_RETURN(const std::string prefix,
                   EncodeKey({{"tenant", tenant}, {"population", population}}));
  const std::string what = CurrentAvatarBasisName(tenant, population);
  ASSIGN_OR_RETURN(std::optional<LogEntry> current,
                   Newest(ReadView(*this), kAvatarCurrent, prefix, what));
  if (!current.has_value()) return absl::NotFoundError(absl::StrCat(what, " not found"));
  return std::move(current->value);
}

absl::Status AssetStore::PutGarment(absl::string_view tenant, absl::string_view garment_id,
                                    absl::string_view bytes) {
  ASSIGN_OR_RETURN(const std::string key,
                   EncodeKey({{"tenant", tenant}, {"garment_id", garment_id}}));
  return PutImmutable(kGarments, key, bytes, kGarmentIds, GarmentName(tenant, garment_id));
}

absl::StatusOr<std::string> AssetStore::GetGarment(absl::string_view tenant,
                                                   absl::string_view garment_id) const {
  ASSIGN_OR_RETURN(const std::string key,
                   EncodeKey({{"tenant", tenant}, {"garment_id", garment_id}}));
  return ReadExisting(ReadView(*this), kGarments, key, GarmentName(tenant, garment_id));
}

absl::StatusOr<std::vector<std::string>> AssetStore::ListGarmentIds(
    absl::string_view tenant) const {
  ASSIGN_OR_RETURN(const std::string prefix, EncodeKey({{"tenant", tenant}}));
  ASSIGN_OR_RETURN(
      std::vector<JobRecord> entries,
      ListRecords(kGarmentIds, prefix, absl::StrCat("garments of tenant '", tenant, "'")));
  std::vector<std::string> ids;
  ids.reserve(entries.size());
  for (JobRecord& entry : entries) ids.push_back(std::move(entry.id));
  return ids;
}

absl::StatusOr<std::map<std::string, std::string>> AssetStore::ListCurrentAvatarBases(
    absl::string_view tenant) const {
  ASSIGN_OR_RETURN(const std::string prefix, EncodeKey({{"tenant", tenant}}));
  const std::string what = absl::StrCat("avatar bases of tenant '", tenant, "'");
  // Keys are the population's then a version (8 bytes): a scan meets every version of every
  // population in order, so the last one seen of each is its current.
  std::map<std::string, std::string> current;
  RETURN_IF_ERROR(Scan(ReadView(*this), kAvatarCurrent, prefix, what,
                       [&](absl::string_view rest, absl::string_view value) -> absl::Status {
                         if (rest.size() < 8) {
                           return absl::DataLossError(
                               absl::StrCat("list ", what, ": stored key is too short"));
                         }
                         rest.remove_suffix(8);
                         ASSIGN_OR_RETURN(std::vector<std::string> ids, DecodeKey(rest));
                         if (ids.size() != 1) {
                           return absl::DataLossError(absl::StrCat(
                               "list ", what, ": stored key has ", ids.size(), " ids, not 1"));
                         }
                         current[ids[0]] = std::string(value);
                         return absl::OkStatus();
                       }));
  return current;
}

absl::StatusOr<ClothingBasisRecord> AssetStore::ReadClothingBasis(const ReadView& view,
                                                                  absl::string_view basis_key,
                                                                  uint64_t version,
                                                                  absl::string_view what) const {
  const std::string version_key = absl::StrCat(basis_key, EncodeVersion(version));
  const std::string version_name = absl::StrCat("version ", version, " of ", what);
  ClothingBasisRecord record;
  record.version = version;
  ASSIGN_OR_RETURN(record.content_id,
                   ReadExisting(view, kClothingVersions, version_key, version_name));
  ASSIGN_OR_RETURN(record.bytes, ReadExisting(view, kClothingBases, version_key, version_name));
  return record;
}

absl::StatusOr<uint64_t> AssetStore::PublishClothingBasis(const ClothingBasisKey& key,
                                                          absl::string_view content_id,
                                                          absl::string_view bytes) {
  ASSIGN_OR_RETURN(const std::string basis_key, EncodeClothingBasisKey(key));
  RETURN_IF_ERROR(ValidateId("content_id", content_id));
  const std::string name = DescribeClothingBasisKey(key);
  const std::string what = absl::StrCat("publish ", name);
  RETURN_IF_ERROR(CheckWritable(what));
  RETURN_IF_ERROR(CheckValueSize(bytes, name));
  std::lock_guard<std::mutex> lock(write_mutex_);
  const ReadView view(*this);
  ASSIGN_OR_RETURN(std::optional<LogEntry> current,
                   Newest(view, kClothingVersions, basis_key, name));
  if (current.has_value() && current->value == content_id) {
    ASSIGN_OR_RETURN(ClothingBasisRecord record,
                     ReadClothingBasis(view, basis_key, current->number, name));
    if (record.bytes != bytes) {
      return absl::AlreadyExistsError(absl::StrCat(
          what, ": current version ", current->number, " has content id '", content_id,
          "' with other bytes (", record.bytes.size(), " stored, ", bytes.size(), " given)"));
    }
    return current->number;
  }
  // Garbage collection keeps the newest version, so the number after it was never used.
  const uint64_t version = current.has_value() ? current->number + 1 : 1;
  const std::string version_key = absl::StrCat(basis_key, EncodeVersion(version));
  rocksdb::WriteBatch batch;
  RETURN_IF_ERROR(FromRocksDbStatus(
      batch.Put(handles_[kClothingBases], ToSlice(version_key), ToSlice(bytes)), what));
  RETURN_IF_ERROR(FromRocksDbStatus(
      batch.Put(handles_[kClothingVersions], ToSlice(version_key), ToSlice(content_id)), what));
  RETURN_IF_ERROR(Write(&batch, /*sync=*/true, what));
  return version;
}

absl::StatusOr<ClothingBasisRecord> AssetStore::GetClothingBasis(const ClothingBasisKey& key,
                                                                 uint64_t version) const {
  ASSIGN_OR_RETURN(const std::string basis_key, EncodeClothingBasisKey(key));
  return ReadClothingBasis(ReadView(*this), basis_key, version, DescribeClothingBasisKey(key));
}

absl::StatusOr<AssetStore::LogEntry> AssetStore::CurrentClothingVersion(
    const ReadView& view, absl::string_view basis_key, absl::string_view name) const {
  ASSIGN_OR_RETURN(std::optional<LogEntry> current,
                   Newest(view, kClothingVersions, basis_key, name));
  if (!current.has_value()) {
    return absl::NotFoundError(absl::StrCat("current version of ", name, " not found"));
  }
  return *std::move(current);
}

absl::StatusOr<ClothingBasisRecord> AssetStore::GetCurrentClothingBasis(
    const ClothingBasisKey& key) const {
  ASSIGN_OR_RETURN(const std::string basis_key, EncodeClothingBasisKey(key));
  const std::string name = DescribeClothingBasisKey(key);
  const ReadView view(*this);
  ASSIGN_OR_RETURN(LogEntry current, CurrentClothingVersion(view, basis_key, name));
  ASSIGN_OR_RETURN(std::string bytes,
                   ReadExisting(view, kClothingBases,
                                absl::StrCat(basis_key, EncodeVersion(current.number)),
                                absl::StrCat("version ", current.number, " of ", name)));
  return ClothingBasisRecord{current.number, std::move(current.value), std::move(bytes)};
}

absl::StatusOr<ClothingBasisVersion> AssetStore::GetCurrentClothingBasisVersion(
    const ClothingBasisKey& key) const {
  ASSIGN_OR_RETURN(const std::string basis_key, EncodeClothingBasisKey(key));
  const ReadView view(*this);
  ASSIGN_OR_RETURN(LogEntry current,
                   CurrentClothingVersion(view, basis_key, DescribeClothingBasisKey(key)));
  return ClothingBasisVersion{current.number, std::move(current.value)};
}

absl::StatusOr<std::vector<ClothingBasisVersion>> AssetStore::ListClothingBasisVersions(
    const ClothingBasisKey& key) const {
  ASSIGN_OR_RETURN(const std::string basis_key, EncodeClothingBasisKey(key));
  const ReadView view(*this);
  std::vector<ClothingBasisVersion> versions;
  RETURN_IF_ERROR(Scan(view, kClothingVersions, basis_key,
                       absl::StrCat("versions of ", DescribeClothingBasisKey(key)),
                       [&](absl::string_view rest, absl::string_view content_id) -> absl::Status {
                         ASSIGN_OR_RETURN(const uint64_t version, DecodeVersion(rest));
                         versions.push_back({version, std::string(content_id)});
                         return absl::OkStatus();
                       }));
  return versions;
}

absl::StatusOr<uint64_t> AssetStore::GarbageCollectClothingBases(const ClothingBasisKey& key,
                                                                 uint64_t keep_versions) {
  ASSIGN_OR_RETURN(const std::string basis_key, EncodeClothingBasisKey(key));
  const std::string what =
      absl::StrCat("garbage-collect versions of ", DescribeClothingBasisKey(key));
  RETURN_IF_ERROR(CheckWritable(what));
  std::lock_guard<std::mutex> lock(write_mutex_);
  const ReadView view(*this);
  std::vector<uint64_t> versions;
  RETURN_IF_ERROR(Scan(view, kClothingVersions, basis_key, what,
                       [&](absl::string_view rest, absl::string_view) -> absl::Status {
                         ASSIGN_OR_RETURN(const uint64_t version, DecodeVersion(rest));
                         versions.push_back(version);
                         return absl::OkStatus();
                       }));
  // The newest version is the current one: it stays even when keep_versions is 0.
  const uint64_t keep = std::max<uint64_t>(keep_versions, 1);
  if (versions.size() <= keep) return 0;
  const uint64_t deleted = versions.size() - keep;
  rocksdb::WriteBatch batch;
  for (uint64_t i = 0; i < deleted; ++i) {
    const std::string version_key = absl::StrCat(basis_key, EncodeVersion(versions[i]));
    RETURN_IF_ERROR(
        FromRocksDbStatus(batch.Delete(handles_[kClothingBases], ToSlice(version_key)), what));
    RETURN_IF_ERROR(FromRocksDbStatus(
        batch.Delete(handles_[kClothingVersions], ToSlice(version_key)), what));
  }
  RETURN_IF_ERROR(Write(&batch, /*sync=*/true, what));
  return deleted;
}

absl::Status AssetStore::PutDrapeResult(absl::string_view drape_key, absl::string_view bytes) {
  return Commit(AssetWrite().PutDrapeResult(drape_key, std::string(bytes)), /*sync=*/true);
}

absl::StatusOr<std::string> AssetStore::GetDrapeResult(absl::string_view drape_key) const {
  ASSIGN_OR_RETURN(const std::string key, EncodeKey({{"drape_key", drape_key}}));
  return ReadExisting(ReadView(*this), kDrapeResults, key,
                      absl::StrCat("drape result '", drape_key, "'"));
}

absl::Status AssetStore::PutBuild(absl::string_view build_id, absl::string_view bytes,
                                  bool sync) {
  return Commit(AssetWrite().PutBuild(build_id, std::string(bytes)), sync);
}

absl::StatusOr<std::string> AssetStore::GetBuild(absl::string_view build_id) const {
  ASSIGN_OR_RETURN(const std::string key, EncodeKey({{"build_id", build_id}}));
  return ReadExisting(ReadView(*this), kBuilds, key, absl::StrCat("build '", build_id, "'"));
}

absl::StatusOr<std::vector<JobRecord>> AssetStore::ListBuilds() const {
  return ListRecords(kBuilds, "", "builds");
}

absl::Status AssetStore::PutTask(absl::string_view build_id, absl::string_view task_id,
                                 absl::string_view bytes, bool sync) {
  return Commit(AssetWrite().PutTask(build_id, task_id, std::string(bytes)), sync);
}

absl::StatusOr<std::string> AssetStore::GetTask(absl::string_view build_id,
                                                absl::string_view task_id) const {
  ASSIGN_OR_RETURN(const std::string key,
                   EncodeKey({{"build_id", build_id}, {"task_id", task_id}}));
  return ReadExisting(ReadView(*this), kTasks, key,
                      absl::StrCat("task '", task_id, "' of build '", build_id, "'"));
}

absl::StatusOr<std::vector<JobRecord>> AssetStore::ListTasks(absl::string_view build_id) const {
  ASSIGN_OR_RETURN(const std::string prefix, EncodeKey({{"build_id", build_id}}));
  return ListRecords(kTasks, prefix, absl::StrCat("tasks of build '", build_id, "'"));
}

absl::Status AssetStore::Commit(const AssetWrite& write, bool sync) {
  RETURN_IF_ERROR(write.status());
  const std::vector<AssetWrite::Change>& changes = write.changes();
  const std::string what = changes.size() == 1
                               ? absl::StrCat("write ", changes[0].description)
                               : absl::StrCat("commit of ", changes.size(), " changes");
  RETURN_IF_ERROR(CheckWritable(what));
  bool puts_immutable = false;
  for (const AssetWrite::Change& change : changes) {
    if (change.action != AssetWrite::Action::kPut) continue;
    RETURN_IF_ERROR(CheckValueSize(change.value, change.description));
    puts_immutable = puts_immutable || change.kind == AssetWrite::Kind::kDrapeResult;
  }
  // Job state needs no check, so commits of it alone leave the mutex to the immutability
  // checks and let RocksDB group their WAL syncs.
  std::unique_lock<std::mutex> lock(write_mutex_, std::defer_lock);
  std::optional<ReadView> view;
  if (puts_immutable) {
    lock.lock();
    view.emplace(*this);
  }
  // Drape results this write puts (their bytes) or deletes (nullopt), by key: a later change
  // to the same record must be checked against them rather than against the stored record.
  absl::flat_hash_map<absl::string_view, std::optional<absl::string_view>> written_results;
  rocksdb::WriteBatch batch;
  for (const AssetWrite::Change& change : changes) {
    Column column = kDefault;
    switch (change.kind) {
      case AssetWrite::Kind::kBuild:
        column = kBuilds;
        break;
      case AssetWrite::Kind::kTask:
        column = kTasks;
        break;
      case AssetWrite::Kind::kDrapeResult:
        column = kDrapeResults;
        break;
    }
    rocksdb::ColumnFamilyHandle* handle = handles_[column];
    rocksdb::Status status;
    switch (change.action) {
      case AssetWrite::Action::kPut: {
        if (column == kDrapeResults) {
          std::optional<std::string> read;
          std::optional<absl::string_view> stored;
          if (auto written = written_results.find(change.key); written != written_results.end()) {
            stored = written->second;
          } else {
            ASSIGN_OR_RETURN(read, Read(*view, column, change.key, change.description));
            stored = read;
          }
          ASSIGN_OR_RETURN(const bool is_new,
                           IsNewRecord(stored, change.value, change.description));
          written_results[change.key] = change.value;
          if (!is_new) continue;
        }
        status = batch.Put(handle, ToSlice(change.key), ToSlice(change.value));
        break;
      }
      case AssetWrite::Action::kDelete:
        if (column == kDrapeResults) written_results[change.key] = std::nullopt;
        status = batch.Delete(handle, ToSlice(change.key));
        break;
      case AssetWrite::Action::kDeleteRange:
        status = batch.DeleteRange(handle, ToSlice(change.key), ToSlice(change.value));
        break;
    }
    RETURN_IF_ERROR(FromRocksDbStatus(status, absl::StrCat(what, ": ", change.description)));
  }
  if (batch.Count() == 0) return absl::OkStatus();
  return Write(&batch, sync, what);
}

absl::Status AssetStore::CreateCheckpoint(const std::filesystem::path& dir) {
  const std::string what = absl::StrCat("checkpoint to ", dir.string());
  if (options_.mode != OpenMode::kPrimary) {
    return absl::FailedPreconditionError(
        absl::StrCat(what, ": checkpoints are taken from the primary"));
  }
  std::error_code error;
  if (std::filesystem::exists(dir, error)) {
    return absl::AlreadyExistsError(absl::StrCat(what, ": the folder must not exist"));
  }
  rocksdb::Checkpoint* checkpoint = nullptr;
  RETURN_IF_ERROR(FromRocksDbStatus(rocksdb::Checkpoint::Create(db_.get(), &checkpoint), what));
  const std::unique_ptr<rocksdb::Checkpoint> owned(checkpoint);
  // RocksDB wants an absolute path. The default log_size_for_flush (0) flushes the memtables
  // first, so the copy hard-links table and blob files rather than copying WAL files.
  return FromRocksDbStatus(
      owned->CreateCheckpoint(std::filesystem::absolute(dir).string()), what);
}

absl::Status AssetStore::TryCatchUpWithPrimary() {
  if (options_.mode != OpenMode::kSecondary) {
    return absl::FailedPreconditionError(
        "catch up with primary: the asset store is not open as a secondary");
  }
  std::unique_lock<std::shared_mutex> lock(catch_up_mutex_);
  return FromRocksDbStatus(db_->TryCatchUpWithPrimary(), "catch up with primary");
}

}  // namespace fitbase::storage
