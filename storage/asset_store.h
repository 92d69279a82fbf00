#ifndef FITBASE_STORAGE_ASSET_STORE_H_
#define FITBASE_STORAGE_ASSET_STORE_H_

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>
#include <vector>

#include "absl/functional/function_ref.h"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "storage/asset_write.h"
#include "storage/record_key.h"

namespace rocksdb {
class ColumnFamilyHandle;
class DB;
class WriteBatch;
}  // namespace rocksdb

namespace fitbase::storage {

enum class OpenMode {
  // The one writer (a coordinator). Creates the database if it is missing.
  kPrimary,
  // Reads a database no process writes, such as a checkpoint.
  kReadOnly,
  // Reads a live primary's database from another process (a fit service); sees the primary's
  // writes up to the last TryCatchUpWithPrimary. Refused (FAILED_PRECONDITION) for a database
  // with blob files.
  kSecondary,
};

struct OpenOptions {
  OpenMode mode = OpenMode::kPrimary;
  // kSecondary only: a folder of the secondary's own for its info log; created if missing.
  std::filesystem::path secondary_path;
  // Puts of larger values fail with RESOURCE_EXHAUSTED.
  size_t max_value_bytes = size_t{256} << 20;
  // kPrimary: whether values of at least min_blob_bytes, in the column families of avatar
  // bases, garments, clothing bases and drape results, go to blob files instead of the LSM
  // tree, so compactions do not rewrite them. Fixed when the database is created: opening it
  // with the other value is FAILED_PRECONDITION. RocksDB secondaries cannot read blob files
  // (facebook/rocksdb#13296, they crash): a database that secondaries read is created without
  // them; with them, read replicas are checkpoints opened kReadOnly.
  bool blob_files = true;
  uint64_t min_blob_bytes = 4096;
};

// One published version of a clothing basis.
struct ClothingBasisVersion {
  uint64_t version = 0;
  std::string content_id;
};

struct ClothingBasisRecord {
  uint64_t version = 0;
  std::string content_id;
  std::string bytes;
};

// A build or a task and its state.
struct JobRecord {
  std::string id;
  std::string bytes;
};

// The asset store: one RocksDB database with a column family per kind of record. Records are
// opaque bytes (callers serialize protos deterministically).
//
// - Avatar bases (by content id), garments (per tenant), drape results (by content key) and
//   clothing basis versions are immutable: putting an id again with the same bytes writes
//   nothing and succeeds, with different bytes fails with ALREADY_EXISTS and writes nothing.
// - A current pointer per (tenant, population) names the avatar basis that serves; per
//   clothing basis key, the current version is the one that serves. A publication writes the
//   record and its pointer (for a clothing basis, its version index entry) in one atomic,
//   synced WriteBatch.
// - Clothing basis versions are numbered 1, 2, ... per key in publication order, never reused;
//   the current one is always the newest. Old versions stay readable until
//   GarbageCollectClothingBases deletes them.
// - Builds and tasks are mutable job state.
//
// Pointers are append-only logs whose newest entry is current (for clothing bases, the version
// index itself), so every key is written once: a RocksDB secondary keeps serving the old value
// of an overwritten or deleted key after the primary flushes the new one (the entries it
// replayed from the WAL stay in its memtable, facebook/rocksdb#15051). A secondary therefore
// sees every publication exactly, but may keep showing garbage-collected versions and stale
// job state: read those on the primary.
//
// Every write goes through the WAL; the immutable records, publications and garbage
// collection are synced (fsync before returning), job state when the caller asks. Ids are
// validated as record_key.h says; an invalid one is INVALID_ARGUMENT naming its field. Errors
// name the operation and the record. All methods are safe to call from several threads.
class AssetStore {
 public:
  // Opens the database at `path` as `options.mode` says.
  static absl::StatusOr<std::unique_ptr<AssetStore>> Open(const std::filesystem::path& path,
                                                          const OpenOptions& options);
  ~AssetStore();
  AssetStore(const AssetStore&) = delete;
  AssetStore& operator=(const AssetStore&) = delete;

  // Avatar bases, by content id.
  absl::Status PutAvatarBasis(absl::string_view avatar_basis_id, absl::string_view bytes);
  absl::StatusOr<std::string> GetAvatarBasis(absl::string_view avatar_basis_id) const;
  // Puts the avatar basis (as PutAvatarBasis) and makes it the current one of `tenant`'s
  // `population`, atomically.
  absl::Status PublishAvatarBasis(absl::string_view tenant, absl::string_view population,
                                  absl::string_view avatar_basis_id, absl::string_view bytes);
  // NOT_FOUND when none was published.
  absl::StatusOr<std::string> GetCurrentAvatarBasisId(absl::string_view tenant,
                                                      absl::string_view population) const;

  // Garments, per tenant: another tenant's garment is NOT_FOUND.
  absl::Status PutGarment(absl::string_view tenant, absl::string_view garment_id,
                          absl::string_view bytes);
  absl::StatusOr<std::string> GetGarment(absl::string_view tenant,
                                         absl::string_view garment_id) const;
  // In byte order of the ids.
  absl::StatusOr<std::vector<std::string>> ListGarmentIds(absl::string_view tenant) const;
  // The tenant's populations with a current avatar basis, and that basis's id, by name.
  absl::StatusOr<std::map<std::string, std::string>> ListCurrentAvatarBases(
      absl::string_view tenant) const;

  // Publishes `bytes` (whose content hash is `content_id`) as the next version of `key` and
  // returns its number. When the current version already has `content_id` and these bytes,
  // returns that version and writes nothing, so a coordinator may retry a publication; the
  // same content id with other bytes is ALREADY_EXISTS.
  absl::StatusOr<uint64_t> PublishClothingBasis(const ClothingBasisKey& key,
                                                absl::string_view content_id,
                                                absl::string_view bytes);
  // NOT_FOUND when the version does not exist (never published, or garbage-collected).
  absl::StatusOr<ClothingBasisRecord> GetClothingBasis(const ClothingBasisKey& key,
                                                       uint64_t version) const;
  // NOT_FOUND when none was published.
  absl::StatusOr<ClothingBasisRecord> GetCurrentClothingBasis(const ClothingBasisKey& key) const;
  // The current version's number and content id, from the index alone (no blob read): how a
  // server checks cheaply whether its cached copy is still current. NOT_FOUND when none.
  absl::StatusOr<ClothingBasisVersion> GetCurrentClothingBasisVersion(
      const ClothingBasisKey& key) const;
  // Oldest first; empty when none was published.
  absl::StatusOr<std::vector<ClothingBasisVersion>> ListClothingBasisVersions(
      const ClothingBasisKey& key) const;
  // Deletes every version of `key` but the newest `keep_versions`, and never the current (newest)
  // one, so 0 keeps just that; returns how many it deleted.
  absl::StatusOr<uint64_t> GarbageCollectClothingBases(const ClothingBasisKey& key,
                                                       uint64_t keep_versions);

  // Drape results, content-addressed by `drape_key`; immutable, synced.
  absl::Status PutDrapeResult(absl::string_view drape_key, absl::string_view bytes);
  absl::StatusOr<std::string> GetDrapeResult(absl::string_view drape_key) const;

  // Job state. `sync`: fsync the WAL before returning; set it for changes the caller must not
  // lose once it has acted on them, such as a task's completion.
  absl::Status PutBuild(absl::string_view build_id, absl::string_view bytes, bool sync);
  absl::StatusOr<std::string> GetBuild(absl::string_view build_id) const;
  // Every build, in byte order of the ids.
  absl::StatusOr<std::vector<JobRecord>> ListBuilds() const;
  absl::Status PutTask(absl::string_view build_id, absl::string_view task_id,
                       absl::string_view bytes, bool sync);
  absl::StatusOr<std::string> GetTask(absl::string_view build_id,
                                      absl::string_view task_id) const;
  // The build's tasks, in byte order of the ids.
  absl::StatusOr<std::vector<JobRecord>> ListTasks(absl::string_view build_id) const;
  // Applies every change of `write` in one atomic WriteBatch, or none of them.
  absl::Status Commit(const AssetWrite& write, bool sync);

  // Primary only: writes a consistent copy of the database to `dir`, which must not exist (its
  // parent must), hard-linking the table and blob files. Open it kReadOnly as a backup or a
  // read replica.
  absl::Status CreateCheckpoint(const std::filesystem::path& dir);

  // Secondary only: reads the primary's writes since the last catch-up. Reads wait while it
  // runs, so each read sees one state of the primary.
  absl::Status TryCatchUpWithPrimary();

 private:
  class ReadView;
  // Column families, indexes into handles_. kDefault is required by RocksDB and unused, so
  // every kind gets options of its own.
  enum Column : int {
    kDefault,
    kAvatarBases,
    // (tenant, population, publication number) -> avatar basis id.
    kAvatarCurrent,
    kGarments,
    // Key-only indexes of garments and clothing basis versions (with content ids): listing
    // through them reads no blobs, which iterating the records themselves would.
    kGarmentIds,
    // (clothing basis key, version) -> bytes, and -> content id.
    kClothingBases,
    kClothingVersions,
    kDrapeResults,
    kBuilds,
    kTasks,
    kColumnCount,
  };

  // An entry of a log keyed by a prefix and a version number (EncodeVersion).
  struct LogEntry {
    uint64_t number = 0;
    std::string value;
  };

  AssetStore(std::unique_ptr<rocksdb::DB> db, std::vector<rocksdb::ColumnFamilyHandle*> handles,
             const OpenOptions& options);

  absl::Status CheckWritable(absl::string_view what) const;
  absl::Status CheckValueSize(absl::string_view bytes, absl::string_view what) const;
  // The value under `key`, or nullopt when there is none.
  absl::StatusOr<std::optional<std::string>> Read(const ReadView& view, Column column,
                                                  absl::string_view key,
                                                  absl::string_view what) const;
  // The value under `key`; NOT_FOUND "<what> not found" when there is none.
  absl::StatusOr<std::string> ReadExisting(const ReadView& view, Column column,
                                           absl::string_view key, absl::string_view what) const;
  // The entry with the highest number under `prefix`, or nullopt when there is none.
  absl::StatusOr<std::optional<LogEntry>> Newest(const ReadView& view, Column column,
                                                 absl::string_view prefix,
                                                 absl::string_view what) const;
  // Calls `visit` with the rest of each key after `prefix`, and its value, in key order.
  absl::Status Scan(
      const ReadView& view, Column column, absl::string_view prefix, absl::string_view what,
      absl::FunctionRef<absl::Status(absl::string_view rest, absl::string_view value)> visit)
      const;
  // The records of `column` under `prefix` whose keys have one more id.
  absl::StatusOr<std::vector<JobRecord>> ListRecords(Column column, absl::string_view prefix,
                                                     absl::string_view what) const;
  // The newest entry of the clothing basis's version index; NOT_FOUND naming it when none.
  absl::StatusOr<LogEntry> CurrentClothingVersion(const ReadView& view,
                                                  absl::string_view basis_key,
                                                  absl::string_view name) const;
  absl::StatusOr<ClothingBasisRecord> ReadClothingBasis(const ReadView& view,
                                                        absl::string_view basis_key,
                                                        uint64_t version,
                                                        absl::string_view what) const;
  // Puts an immutable record (avatar basis or garment) and, unless `index_column` is
  // kDefault, an empty entry under the same key in `index_column`.
  absl::Status PutImmutable(Column column, absl::string_view key, absl::string_view bytes,
                            Column index_column, absl::string_view what);
  absl::Status Write(rocksdb::WriteBatch* batch, bool sync, absl::string_view what);

  std::unique_ptr<rocksdb::DB> db_;
  std::vector<rocksdb::ColumnFamilyHandle*> handles_;
  const OpenOptions options_;
  // Makes each immutability check and the write after it one step. Only the primary writes,
  // and RocksDB's LOCK file admits one primary process, so an in-process mutex suffices; a
  // TransactionDB would add a lock manager and a different open path for the same guarantee.
  std::mutex write_mutex_;
  // Held shared by reads and exclusively by TryCatchUpWithPrimary: secondaries do not support
  // snapshots, and a catch-up between two reads of one operation would mix two states.
  mutable std::shared_mutex catch_up_mutex_;
};

}  // namespace fitbase::storage

#endif  // FITBASE_STORAGE_ASSET_STORE_H_
