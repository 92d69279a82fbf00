#include "storage/asset_store.h"

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::storage {
namespace {

using core::StatusIs;
using ::testing::ElementsAre;
using ::testing::IsEmpty;

// `size` deterministic bytes that differ with `tag`.
std::string Bytes(absl::string_view tag, size_t size) {
  std::string bytes;
  bytes.reserve(size);
  for (size_t i = 0; i < size; ++i) bytes.push_back(static_cast<char>(tag[i % tag.size()] + i % 7));
  return bytes;
}

std::vector<uint64_t> VersionNumbers(const std::vector<ClothingBasisVersion>& versions) {
  std::vector<uint64_t> numbers;
  for (const ClothingBasisVersion& v : versions) numbers.push_back(v.version);
  return numbers;
}

std::vector<std::string> Ids(const std::vector<JobRecord>& records) {
  std::vector<std::string> ids;
  for (const JobRecord& r : records) ids.push_back(r.id);
  return ids;
}

int CountFilesWithExtension(const std::filesystem::path& dir, const std::string& extension) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    count += entry.path().extension() == extension;
  }
  return count;
}

class AssetStoreTest : public ::testing::Test {
 protected:
  // An empty folder of this test's own: running the whole binary (or repeating a test) puts
  // several tests in one process.
  void SetUp() override {
    dir_ = core::ProcessTempDir() / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }

  std::filesystem::path Dir(absl::string_view name) const { return dir_ / std::string(name); }

  static std::unique_ptr<AssetStore> OpenOrDie(const std::filesystem::path& path,
                                               const OpenOptions& options = {}) {
    auto store = AssetStore::Open(path, options);
    if (!store.ok()) {
      ADD_FAILURE() << store.status();
      std::abort();
    }
    return *std::move(store);
  }

  std::filesystem::path dir_;
  const ClothingBasisKey key_{"acme", "shirt-01", "M", "basis-a", "linear"};
};

TEST_F(AssetStoreTest, AvatarBasisPutIsIdempotentAndImmutable) {
  auto store = OpenOrDie(Dir("db"));
  const std::string bytes = Bytes("basis", 100);
  ASSERT_TRUE(store->PutAvatarBasis("b1", bytes).ok());
  EXPECT_EQ(*store->GetAvatarBasis("b1"), bytes);
  EXPECT_TRUE(store->PutAvatarBasis("b1", bytes).ok());
  EXPECT_THAT(store->PutAvatarBasis("b1", Bytes("other", 100)),
              StatusIs(absl::StatusCode::kAlreadyExists, "avatar basis 'b1' is stored with other"));
  EXPECT_EQ(*store->GetAvatarBasis("b1"), bytes);
  EXPECT_THAT(store->GetAvatarBasis("b2"),
              StatusIs(absl::StatusCode::kNotFound, "avatar basis 'b2' not found"));
}

TEST_F(AssetStoreTest, PublishAvatarBasisMovesThePointerAndPersists) {
  const std::filesystem::path path = Dir("db");
  {
    auto store = OpenOrDie(path);
    EXPECT_THAT(store->GetCurrentAvatarBasisId("acme", "women"),
                StatusIs(absl::StatusCode::kNotFound,
                         "current avatar basis of population 'women' of tenant 'acme' not found"));
    ASSERT_TRUE(store->PublishAvatarBasis("acme", "women", "b1", "one").ok());
    EXPECT_EQ(*store->GetCurrentAvatarBasisId("acme", "women"), "b1");
    ASSERT_TRUE(store->PublishAvatarBasis("acme", "women", "b2", "two").ok());
    // Republishing is idempotent; a known id with other bytes changes nothing.
    ASSERT_TRUE(store->PublishAvatarBasis("acme", "women", "b2", "two").ok());
    EXPECT_THAT(store->PublishAvatarBasis("acme", "women", "b1", "changed"),
                StatusIs(absl::StatusCode::kAlreadyExists, "avatar basis 'b1'"));
    EXPECT_EQ(*store->GetCurrentAvatarBasisId("acme", "women"), "b2");
    EXPECT_THAT(store->GetCurrentAvatarBasisId("acme", "men"),
                StatusIs(absl::StatusCode::kNotFound, "population 'men'"));
    EXPECT_THAT(store->GetCurrentAvatarBasisId("globex", "women"),
                StatusIs(absl::StatusCode::kNotFound, "tenant 'globex'"));
  }
  auto store = OpenOrDie(path);
  EXPECT_EQ(*store->GetCurrentAvatarBasisId("acme", "women"), "b2");
  ASSERT_TRUE(store->PublishAvatarBasis("acme", "men", "b1", "one").ok());
  ASSERT_TRUE(store->PublishAvatarBasis("acme2", "kids", "b1", "one").ok());
  // Each population's current, of this tenant only ("acme" is a prefix of "acme2").
  EXPECT_EQ(*store->ListCurrentAvatarBases("acme"),
            (std::map<std::string, std::string>{{"men", "b1"}, {"women", "b2"}}));
  EXPECT_TRUE(store->ListCurrentAvatarBases("globex")->empty());
  EXPECT_EQ(*store->GetAvatarBasis("b1"), "one");
  EXPECT_EQ(*store->GetAvatarBasis("b2"), "two");
}

TEST_F(AssetStoreTest, GarmentsBelongToTheirTenant) {
  auto store = OpenOrDie(Dir("db"));
  ASSERT_TRUE(store->PutGarment("acme", "shirt", "acme shirt").ok());
  ASSERT_TRUE(store->PutGarment("acme", "coat", "acme coat").ok());
  ASSERT_TRUE(store->PutGarment("acme2", "shirt", "acme2 shirt").ok());
  ASSERT_TRUE(store->PutGarment("ac", "me", "ac me").ok());
  EXPECT_EQ(*store->GetGarment("acme", "shirt"), "acme shirt");
  EXPECT_EQ(*store->GetGarment("acme2", "shirt"), "acme2 shirt");
  EXPECT_THAT(
      store->GetGarment("globex", "shirt"),
      StatusIs(absl::StatusCode::kNotFound, "garment 'shirt' of tenant 'globex' not found"));
  EXPECT_THAT(*store->ListGarmentIds("acme"), ElementsAre("coat", "shirt"));
  EXPECT_THAT(*store->ListGarmentIds("acme2"), ElementsAre("shirt"));
  EXPECT_THAT(*store->ListGarmentIds("ac"), ElementsAre("me"));
  EXPECT_THAT(*store->ListGarmentIds("a"), IsEmpty());
  EXPECT_TRUE(store->PutGarment("acme", "coat", "acme coat").ok());
  EXPECT_THAT(store->PutGarment("acme", "coat", "new coat"),
              StatusIs(absl::StatusCode::kAlreadyExists, "garment 'coat' of tenant 'acme'"));
  EXPECT_EQ(*store->GetGarment("acme", "coat"), "acme coat");
}

TEST_F(AssetStoreTest, InvalidIdsAreRejectedNamingTheField) {
  auto store = OpenOrDie(Dir("db"));
  EXPECT_THAT(store->PutGarment("acme", "my shirt", "x"),
              StatusIs(absl::StatusCode::kInvalidArgument, "garment_id has byte 0x20"));
  EXPECT_THAT(store->GetGarment("", "shirt"),
              StatusIs(absl::StatusCode::kInvalidArgument, "tenant is empty"));
  EXPECT_THAT(store->PublishAvatarBasis("acme", std::string(300, 'p'), "b1", "x"),
              StatusIs(absl::StatusCode::kInvalidArgument, "population is 300 bytes"));
  ClothingBasisKey bad = key_;
  bad.method = "lin\tear";
  EXPECT_THAT(store->PublishClothingBasis(bad, "c1", "x"),
              StatusIs(absl::StatusCode::kInvalidArgument, "method has byte 0x09"));
  EXPECT_THAT(store->PublishClothingBasis(key_, "", "x"),
              StatusIs(absl::StatusCode::kInvalidArgument, "content_id is empty"));
  EXPECT_THAT(store->PutTask("b1", "", "x", /*sync=*/false),
              StatusIs(absl::StatusCode::kInvalidArgument, "task_id is empty"));
  EXPECT_THAT(store->PutDrapeResult("d\x7f", "x"),
              StatusIs(absl::StatusCode::kInvalidArgument, "drape_key has byte 0x7F"));
  EXPECT_THAT(*store->ListBuilds(), IsEmpty());
  EXPECT_THAT(*store->ListClothingBasisVersions(key_), IsEmpty());
}

TEST_F(AssetStoreTest, ClothingBasisVersionsFollowPublicationOrder) {
  auto store = OpenOrDie(Dir("db"));
  EXPECT_THAT(store->GetCurrentClothingBasis(key_),
              StatusIs(absl::StatusCode::kNotFound, "current version of clothing basis"));
  EXPECT_THAT(store->GetCurrentClothingBasisVersion(key_),
              StatusIs(absl::StatusCode::kNotFound, "current version of clothing basis"));
  EXPECT_EQ(*store->PublishClothingBasis(key_, "c1", "one"), 1u);
  // A coordinator's retry of the same publication is the same version.
  EXPECT_EQ(*store->PublishClothingBasis(key_, "c1", "one"), 1u);
  EXPECT_THAT(store->PublishClothingBasis(key_, "c1", "uno"),
              StatusIs(absl::StatusCode::kAlreadyExists, "current version 1 has content id 'c1'"));
  EXPECT_EQ(*store->PublishClothingBasis(key_, "c2", "two"), 2u);
  EXPECT_EQ(*store->PublishClothingBasis(key_, "c3", "three"), 3u);
  // Going back to earlier content is a new publication.
  EXPECT_EQ(*store->PublishClothingBasis(key_, "c1", "one"), 4u);

  auto current = store->GetCurrentClothingBasis(key_);
  ASSERT_TRUE(current.ok()) << current.status();
  EXPECT_EQ(current->version, 4u);
  EXPECT_EQ(current->content_id, "c1");
  EXPECT_EQ(current->bytes, "one");
  auto version = store->GetCurrentClothingBasisVersion(key_);
  ASSERT_TRUE(version.ok()) << version.status();
  EXPECT_EQ(version->version, 4u);
  EXPECT_EQ(version->content_id, "c1");
  auto second = store->GetClothingBasis(key_, 2);
  ASSERT_TRUE(second.ok()) << second.status();
  EXPECT_EQ(second->content_id, "c2");
  EXPECT_EQ(second->bytes, "two");
  EXPECT_THAT(store->GetClothingBasis(key_, 5),
              StatusIs(absl::StatusCode::kNotFound, "version 5 of clothing basis"));

  auto versions = store->ListClothingBasisVersions(key_);
  ASSERT_TRUE(versions.ok()) << versions.status();
  EXPECT_THAT(VersionNumbers(*versions), ElementsAre(1, 2, 3, 4));
  EXPECT_EQ((*versions)[2].content_id, "c3");

  ClothingBasisKey large = key_;
  large.size = "L";
  EXPECT_THAT(*store->ListClothingBasisVersions(large), IsEmpty());
  EXPECT_EQ(*store->PublishClothingBasis(large, "c9", "nine"), 1u);
  EXPECT_EQ(store->GetCurrentClothingBasis(key_)->version, 4u);
}

TEST_F(AssetStoreTest, GarbageCollectionKeepsNewestVersionsAndTheCurrentOne) {
  auto store = OpenOrDie(Dir("db"));
  EXPECT_EQ(*store->GarbageCollectClothingBases(key_, 0), 0u);
  for (int v = 1; v <= 5; ++v) {
    ASSERT_EQ(*store->PublishClothingBasis(key_, absl::StrCat("c", v), absl::StrCat("bytes", v)),
              static_cast<uint64_t>(v));
  }
  EXPECT_EQ(*store->GarbageCollectClothingBases(key_, 2), 3u);
  EXPECT_THAT(VersionNumbers(*store->ListClothingBasisVersions(key_)), ElementsAre(4, 5));
  EXPECT_THAT(store->GetClothingBasis(key_, 3), StatusIs(absl::StatusCode::kNotFound, ""));
  EXPECT_EQ(store->GetClothingBasis(key_, 4)->bytes, "bytes4");

  EXPECT_EQ(*store->GarbageCollectClothingBases(key_, 0), 1u);
  EXPECT_THAT(VersionNumbers(*store->ListClothingBasisVersions(key_)), ElementsAre(5));
  EXPECT_EQ(store->GetCurrentClothingBasis(key_)->bytes, "bytes5");
  EXPECT_EQ(*store->GarbageCollectClothingBases(key_, 0), 0u);
  // Numbers of collected versions are never handed out again.
  EXPECT_EQ(*store->PublishClothingBasis(key_, "c6", "bytes6"), 6u);
}

TEST_F(AssetStoreTest, ReadersNeverSeeAHalfPublishedOrCollectedVersion) {
  auto store = OpenOrDie(Dir("db"));
  ASSERT_TRUE(store->PublishClothingBasis(key_, "c0", "bytes of c0").ok());
  std::atomic<bool> done = false;
  std::thread publisher([&] {
    for (int v = 1; v <= 50; ++v) {
      const std::string content_id = absl::StrCat("c", v);
      EXPECT_TRUE(store->PublishClothingBasis(key_, content_id, "bytes of " + content_id).ok());
      EXPECT_TRUE(store->GarbageCollectClothingBases(key_, 0).ok());
    }
    done = true;
  });
  uint64_t last_version = 0;
  int reads = 0;
  while (!done || reads == 0) {
    auto current = store->GetCurrentClothingBasis(key_);
    ASSERT_TRUE(current.ok()) << current.status();
    EXPECT_EQ(current->bytes, "bytes of " + current->content_id);
    EXPECT_GE(current->version, last_version);
    last_version = current->version;
    ++reads;
  }
  publisher.join();
  EXPECT_EQ(store->GetCurrentClothingBasis(key_)->version, 51u);
}

TEST_F(AssetStoreTest, ConcurrentConflictingPutsHaveOneWinner) {
  auto store = OpenOrDie(Dir("db"));
  constexpr int kIds = 20;
  std::vector<absl::Status> results[2];
  std::vector<std::thread> writers;
  for (int w = 0; w < 2; ++w) {
    writers.emplace_back([&, w] {
      for (int i = 0; i < kIds; ++i) {
        results[w].push_back(
            store->PutGarment("acme", absl::StrCat("g", i), absl::StrCat("writer", w)));
      }
    });
  }
  for (std::thread& writer : writers) writer.join();
  for (int i = 0; i < kIds; ++i) {
    const bool first_won = results[0][i].ok();
    EXPECT_NE(first_won, results[1][i].ok()) << i;
    EXPECT_THAT(results[first_won ? 1 : 0][i], StatusIs(absl::StatusCode::kAlreadyExists, ""));
    EXPECT_EQ(*store->GetGarment("acme", absl::StrCat("g", i)),
              first_won ? "writer0" : "writer1");
  }
}

TEST_F(AssetStoreTest, DrapeResultsAreContentAddressed) {
  auto store = OpenOrDie(Dir("db"));
  ASSERT_TRUE(store->PutDrapeResult("d1", "drape").ok());
  EXPECT_TRUE(store->PutDrapeResult("d1", "drape").ok());
  EXPECT_THAT(store->PutDrapeResult("d1", "other"),
              StatusIs(absl::StatusCode::kAlreadyExists, "drape result 'd1'"));
  EXPECT_EQ(*store->GetDrapeResult("d1"), "drape");
  EXPECT_THAT(store->GetDrapeResult("d2"), StatusIs(absl::StatusCode::kNotFound, "'d2' not found"));
}

TEST_F(AssetStoreTest, JobStateIsMutableAndListedInOrder) {
  auto store = OpenOrDie(Dir("db"));
  ASSERT_TRUE(store->PutBuild("build-2", "queued", /*sync=*/false).ok());
  ASSERT_TRUE(store->PutBuild("build-1", "queued", /*sync=*/false).ok());
  ASSERT_TRUE(store->PutBuild("build-1", "running", /*sync=*/true).ok());
  EXPECT_EQ(*store->GetBuild("build-1"), "running");
  EXPECT_THAT(Ids(*store->ListBuilds()), ElementsAre("build-1", "build-2"));
  EXPECT_EQ((*store->ListBuilds())[0].bytes, "running");

  ASSERT_TRUE(store->PutTask("build-1", "t2", "leased", /*sync=*/false).ok());
  ASSERT_TRUE(store->PutTask("build-1", "t1", "leased", /*sync=*/false).ok());
  ASSERT_TRUE(store->PutTask("build-2", "t1", "leased", /*sync=*/false).ok());
  EXPECT_THAT(Ids(*store->ListTasks("build-1")), ElementsAre("t1", "t2"));
  EXPECT_THAT(Ids(*store->ListTasks("build-2")), ElementsAre("t1"));
  EXPECT_THAT(*store->ListTasks("build-3"), IsEmpty());
  EXPECT_THAT(store->GetTask("build-2", "t2"),
              StatusIs(absl::StatusCode::kNotFound, "task 't2' of build 'build-2' not found"));

  // A task's completion, its drape result and the build's progress land together.
  AssetWrite completion;
  completion.PutTask("build-1", "t1", "done:d1")
      .PutDrapeResult("d1", "drape")
      .PutBuild("build-1", "1/2 done");
  ASSERT_TRUE(store->Commit(completion, /*sync=*/true).ok());
  EXPECT_EQ(*store->GetTask("build-1", "t1"), "done:d1");
  EXPECT_EQ(*store->GetDrapeResult("d1"), "drape");
  EXPECT_EQ(*store->GetBuild("build-1"), "1/2 done");
  // Committing it again (a retried completion) is harmless.
  ASSERT_TRUE(store->Commit(completion, /*sync=*/true).ok());

  ASSERT_TRUE(store->Commit(AssetWrite().DeleteBuild("build-1"), /*sync=*/true).ok());
  EXPECT_THAT(store->GetBuild("build-1"), StatusIs(absl::StatusCode::kNotFound, ""));
  EXPECT_THAT(*store->ListTasks("build-1"), IsEmpty());
  EXPECT_THAT(Ids(*store->ListTasks("build-2")), ElementsAre("t1"));
  EXPECT_THAT(Ids(*store->ListBuilds()), ElementsAre("build-2"));
}

TEST_F(AssetStoreTest, CommitIsAllOrNothing) {
  auto store = OpenOrDie(Dir("db"));
  ASSERT_TRUE(store->PutDrapeResult("d1", "drape").ok());
  AssetWrite conflicting;
  conflicting.PutBuild("b", "done").PutTask("b", "t", "done").PutDrapeResult("d1", "other");
  EXPECT_THAT(store->Commit(conflicting, /*sync=*/true),
              StatusIs(absl::StatusCode::kAlreadyExists, "drape result 'd1'"));
  AssetWrite invalid;
  invalid.PutBuild("b", "done").PutTask("b", "bad task", "done");
  EXPECT_THAT(store->Commit(invalid, /*sync=*/true),
              StatusIs(absl::StatusCode::kInvalidArgument, "task_id"));
  AssetWrite twice;
  twice.PutBuild("b", "done").PutDrapeResult("d2", "x").PutDrapeResult("d2", "y");
  EXPECT_THAT(store->Commit(twice, /*sync=*/true),
              StatusIs(absl::StatusCode::kAlreadyExists, "drape result 'd2'"));
  EXPECT_THAT(*store->ListBuilds(), IsEmpty());
  EXPECT_THAT(*store->ListTasks("b"), IsEmpty());
  EXPECT_THAT(store->GetDrapeResult("d2"), StatusIs(absl::StatusCode::kNotFound, ""));

  // A result deleted earlier in the same write may be put again with other bytes.
  AssetWrite replace;
  replace.DeleteDrapeResult("d1").PutDrapeResult("d1", "redone");
  ASSERT_TRUE(store->Commit(replace, /*sync=*/true).ok());
  EXPECT_EQ(*store->GetDrapeResult("d1"), "redone");
}

TEST_F(AssetStoreTest, OversizeValuesAreRefused) {
  OpenOptions options;
  options.max_value_bytes = 100;
  auto store = OpenOrDie(Dir("db"), options);
  EXPECT_TRUE(store->PutAvatarBasis("b1", std::string(100, 'x')).ok());
  EXPECT_THAT(store->PutAvatarBasis("b2", std::string(101, 'x')),
              StatusIs(absl::StatusCode::kResourceExhausted,
                       "avatar basis 'b2' is 101 bytes, more than the limit of 100"));
  EXPECT_THAT(store->PublishClothingBasis(key_, "c1", std::string(101, 'x')),
              StatusIs(absl::StatusCode::kResourceExhausted, "101 bytes"));
  AssetWrite oversize;
  oversize.PutBuild("b", "x").PutTask("b", "t", std::string(101, 'x'));
  EXPECT_THAT(store->Commit(oversize, /*sync=*/false),
              StatusIs(absl::StatusCode::kResourceExhausted, "task 't' of build 'b'"));
  EXPECT_THAT(store->GetAvatarBasis("b2"), StatusIs(absl::StatusCode::kNotFound, ""));
  EXPECT_THAT(*store->ListClothingBasisVersions(key_), IsEmpty());
  EXPECT_THAT(*store->ListBuilds(), IsEmpty());
}

TEST_F(AssetStoreTest, CheckpointIsAFrozenReadOnlyCopyWithBlobFiles) {
  const std::filesystem::path path = Dir("db");
  const std::filesystem::path checkpoint = Dir("checkpoint");
  auto store = OpenOrDie(path);
  const std::string large = Bytes("large", 64 << 10);
  ASSERT_TRUE(store->PublishClothingBasis(key_, "c1", large).ok());
  ASSERT_TRUE(store->PutGarment("acme", "shirt", "small").ok());
  ASSERT_TRUE(store->CreateCheckpoint(checkpoint).ok());
  EXPECT_THAT(store->CreateCheckpoint(checkpoint),
              StatusIs(absl::StatusCode::kAlreadyExists, "must not exist"));
  ASSERT_TRUE(store->PublishClothingBasis(key_, "c2", "later").ok());
  ASSERT_TRUE(store->PutGarment("acme", "coat", "later").ok());

  // The checkpoint flushed the memtables: the large value went to a blob file, shared by
  // hard link with the live database.
  EXPECT_GE(CountFilesWithExtension(checkpoint, ".blob"), 1);
  EXPECT_GE(CountFilesWithExtension(path, ".blob"), 1);

  OpenOptions read_only;
  read_only.mode = OpenMode::kReadOnly;
  auto replica = OpenOrDie(checkpoint, read_only);
  auto current = replica->GetCurrentClothingBasis(key_);
  ASSERT_TRUE(current.ok()) << current.status();
  EXPECT_EQ(current->version, 1u);
  EXPECT_TRUE(current->bytes == large);
  EXPECT_THAT(*replica->ListGarmentIds("acme"), ElementsAre("shirt"));
  EXPECT_THAT(replica->PutGarment("acme", "hat", "x"),
              StatusIs(absl::StatusCode::kFailedPrecondition, "open read-only"));
  EXPECT_THAT(replica->CreateCheckpoint(Dir("again")),
              StatusIs(absl::StatusCode::kFailedPrecondition, "from the primary"));
  EXPECT_EQ(store->GetCurrentClothingBasis(key_)->version, 2u);
}

TEST_F(AssetStoreTest, SecondarySeesPublicationsAfterCatchingUp) {
  const std::filesystem::path path = Dir("db");
  OpenOptions primary_options;
  primary_options.blob_files = false;
  auto primary = OpenOrDie(path, primary_options);
  OpenOptions secondary_options;
  secondary_options.mode = OpenMode::kSecondary;
  secondary_options.secondary_path = Dir("secondary");
  auto secondary = OpenOrDie(path, secondary_options);

  ASSERT_TRUE(primary->PublishAvatarBasis("acme", "women", "b1", "basis").ok());
  ASSERT_EQ(*primary->PublishClothingBasis(key_, "c1", "one"), 1u);
  EXPECT_THAT(secondary->GetCurrentClothingBasis(key_), StatusIs(absl::StatusCode::kNotFound, ""));
  ASSERT_TRUE(secondary->TryCatchUpWithPrimary().ok());
  EXPECT_EQ(*secondary->GetCurrentAvatarBasisId("acme", "women"), "b1");
  EXPECT_EQ(secondary->GetCurrentClothingBasis(key_)->bytes, "one");

  // After a flush (the checkpoint's) the secondary catches up from table files, and the
  // pointers it replayed from the WAL before do not hide the new ones.
  const std::string large = Bytes("large", 64 << 10);
  ASSERT_EQ(*primary->PublishClothingBasis(key_, "c2", large), 2u);
  ASSERT_TRUE(primary->PublishAvatarBasis("acme", "women", "b2", "basis 2").ok());
  ASSERT_TRUE(primary->CreateCheckpoint(Dir("checkpoint")).ok());
  EXPECT_EQ(secondary->GetCurrentClothingBasis(key_)->version, 1u);
  ASSERT_TRUE(secondary->TryCatchUpWithPrimary().ok());
  auto current = secondary->GetCurrentClothingBasis(key_);
  ASSERT_TRUE(current.ok()) << current.status();
  EXPECT_EQ(current->version, 2u);
  EXPECT_TRUE(current->bytes == large);
  EXPECT_EQ(*secondary->GetCurrentAvatarBasisId("acme", "women"), "b2");
  EXPECT_THAT(VersionNumbers(*secondary->ListClothingBasisVersions(key_)), ElementsAre(1, 2));

  // And once more from the WAL alone.
  ASSERT_EQ(*primary->PublishClothingBasis(key_, "c3", "three"), 3u);
  ASSERT_TRUE(secondary->TryCatchUpWithPrimary().ok());
  EXPECT_EQ(secondary->GetCurrentClothingBasis(key_)->bytes, "three");

  EXPECT_THAT(secondary->PutDrapeResult("d1", "x"),
              StatusIs(absl::StatusCode::kFailedPrecondition, "as a secondary"));
  EXPECT_THAT(primary->TryCatchUpWithPrimary(),
              StatusIs(absl::StatusCode::kFailedPrecondition, "not open as a secondary"));
}

TEST_F(AssetStoreTest, BlobFilesAreFixedAtCreationAndKeepSecondariesOut) {
  const std::filesystem::path path = Dir("db");
  OpenOptions secondary;
  secondary.mode = OpenMode::kSecondary;
  secondary.secondary_path = Dir("secondary");
  OpenOptions inline_values;
  inline_values.blob_files = false;
  {
    auto store = OpenOrDie(path);
    ASSERT_TRUE(store->PutGarment("acme", "shirt", Bytes("garment", 64 << 10)).ok());
    EXPECT_THAT(AssetStore::Open(path, secondary),
                StatusIs(absl::StatusCode::kFailedPrecondition, "blob files"));
  }
  EXPECT_THAT(AssetStore::Open(path, inline_values),
              StatusIs(absl::StatusCode::kFailedPrecondition,
                       "created with blob_files = true, which is fixed at creation"));

  const std::filesystem::path inline_path = Dir("inline");
  OpenOrDie(inline_path, inline_values);
  EXPECT_THAT(AssetStore::Open(inline_path, OpenOptions()),
              StatusIs(absl::StatusCode::kFailedPrecondition, "blob_files = false"));
  EXPECT_TRUE(AssetStore::Open(inline_path, secondary).ok());
}

TEST_F(AssetStoreTest, OpenErrorsAreStatuses) {
  const std::filesystem::path path = Dir("db");
  OpenOptions read_only;
  read_only.mode = OpenMode::kReadOnly;
  EXPECT_THAT(AssetStore::Open(path, read_only),
              StatusIs(absl::StatusCode::kNotFound, "(read-only): IO error: No such file"));
  OpenOptions secondary;
  secondary.mode = OpenMode::kSecondary;
  EXPECT_THAT(AssetStore::Open(path, secondary),
              StatusIs(absl::StatusCode::kInvalidArgument, "secondary_path is empty"));
  auto primary = OpenOrDie(path);
  // RocksDB's LOCK file admits one primary.
  EXPECT_THAT(AssetStore::Open(path, OpenOptions()),
              StatusIs(absl::StatusCode::kUnavailable, "open asset store"));
}

}  // namespace
}  // namespace fitbase::storage
