// Faults of the distributed build across real processes: `fitbase serve` coordinators and
// workers started as children, killed with SIGKILL, restarted on the same store and port.
#include <csignal>

#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "core/file_util.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "storage/asset_store.h"
#include "tests/build_cluster.h"
#include "tests/child_process.h"

namespace fitbase {
namespace {

using ::testing::HasSubstr;

class BuildFaultsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(std::filesystem::exists(SmallCatalogue() / "ready"))
        << "run through ctest: the small_catalogue fixture makes " << SmallCatalogue();
    dir_ = core::ProcessTempDir() / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    ASSERT_TRUE(core::WriteFileAtomically(dir_ / "keys", TestKeys::FileText()).ok());
  }

  // Starts a coordinator on `port` (0: any) and returns once it serves.
  std::unique_ptr<ChildProcess> StartCoordinator(int port, int lease_seconds) {
    auto child = std::make_unique<ChildProcess>(
        std::vector<std::string>{FITBASE_BINARY, "--data", core::TestDataDir().string(), "serve",
                                 "--role", "coordinator", "--db", (dir_ / "db").string(),
                                 "--listen", absl::StrCat("127.0.0.1:", port), "--api-keys",
                                 (dir_ / "keys").string(), "--lease-seconds",
                                 absl::StrCat(lease_seconds)},
        std::vector<std::string>{}, (dir_ / "coordinator.log").string());
    const std::string line = child->ReadLine();
    EXPECT_TRUE(absl::StartsWith(line, "listening 127.0.0.1:")) << line;
    EXPECT_TRUE(absl::SimpleAtoi(line.substr(line.rfind(':') + 1), &port_));
    clients_ = std::make_unique<Clients>(absl::StrCat("127.0.0.1:", port_));
    return child;
  }

  std::unique_ptr<ChildProcess> StartWorker(const std::string& name) {
    return std::make_unique<ChildProcess>(
        std::vector<std::string>{FITBASE_BINARY, "serve", "--role", "worker", "--coordinator",
                                 absl::StrCat("127.0.0.1:", port_), "--slots", "1", "--name",
                                 name},
        std::vector<std::string>{absl::StrCat("FITBASE_API_KEY=", TestKeys::kWorker)},
        (dir_ / (name + ".log")).string());
  }

  // The small basis and garment on the coordinator; returns the garment id.
  std::string Catalogue() {
    PublishSmallBasis(*clients_);
    const v1::Garment garment = SmallGarment();
    const std::filesystem::path dir = core::TestDataDir() / "clothes" / "female_sportsuit01";
    v1::UploadGarmentRequest upload;
    upload.set_avatar_basis_id(garment.avatar_basis_id());
    upload.add_sizes("M");
    upload.add_sizes("XL");
    upload.mutable_mhclo()->set_name("female_sportsuit01.mhclo");
    upload.mutable_mhclo()->set_content(*core::ReadFileToString(dir / "female_sportsuit01.mhclo"));
    upload.mutable_obj()->set_name("female_sportsuit01.obj");
    upload.mutable_obj()->set_content(*core::ReadFileToString(dir / "female_sportsuit01.obj"));
    v1::UploadGarmentResponse uploaded;
    const grpc::Status status =
        clients_->catalog->UploadGarment(Call(TestKeys::kAdmin).get(), upload, &uploaded);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return uploaded.garment_id();
  }

  // A build whose drapes take about a second each, so a kill lands mid-drape.
  v1::Build SubmitSlowBuild(const std::string& garment_id) {
    v1::SubmitBuildRequest request = SmallBuild(garment_id);
    request.mutable_request()->set_homotopy_steps(20);
    request.mutable_request()->set_relax_steps(30);
    v1::Build build;
    const grpc::Status status =
        clients_->coordinator->SubmitBuild(Call(TestKeys::kAdmin).get(), request, &build);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return build;
  }

  // Follows the build until `done` says so; returns its tasks then.
  template <typename Done>
  v1::GetBuildResponse WatchUntil(const std::string& build_id, Done done) {
    v1::GetBuildRequest request;
    request.set_build_id(build_id);
    auto context = Call(TestKeys::kAdmin, 600);
    auto reader = clients_->coordinator->WatchBuild(context.get(), request);
    v1::Build build;
    while (reader->Read(&build) && !done(build)) {
    }
    context->TryCancel();
    reader->Finish();
    request.set_with_tasks(true);
    v1::GetBuildResponse response;
    EXPECT_TRUE(
        clients_->coordinator->GetBuild(Call(TestKeys::kAdmin).get(), request, &response).ok());
    return response;
  }

  std::filesystem::path dir_;
  int port_ = 0;
  std::unique_ptr<Clients> clients_;
};

TEST_F(BuildFaultsTest, AKilledWorkersTaskIsReleasedAfterExpiryAndPublishedOnce) {
  auto coordinator = StartCoordinator(0, /*lease_seconds=*/2);
  const std::string garment_id = Catalogue();
  auto doomed = StartWorker("doomed");
  const v1::Build build = SubmitSlowBuild(garment_id);
  const v1::GetBuildResponse leased =
      WatchUntil(build.build_id(), [](const v1::Build& b) { return b.tasks_running() > 0; });
  doomed->Signal(SIGKILL);
  doomed->Wait();
  v1::Task victim;
  for (const v1::Task& task : leased.tasks()) {
    if (task.phase() == v1::TASK_LEASED) victim = task;
  }
  ASSERT_EQ(victim.worker(), "doomed/0");

  auto rescuer = StartWorker("rescuer");
  const v1::GetBuildResponse done = WatchUntil(build.build_id(), [](const v1::Build& b) {
    return b.phase() == v1::BUILD_SUCCEEDED || b.phase() == v1::BUILD_FAILED;
  });
  ASSERT_EQ(done.build().phase(), v1::BUILD_SUCCEEDED) << done.build().error();
  for (const v1::Task& task : done.tasks()) {
    if (task.task_id() != victim.task_id()) continue;
    EXPECT_EQ(task.attempts(), 1u);
    EXPECT_EQ(task.leases(), 2u);
    EXPECT_THAT(task.error(), HasSubstr("doomed/0"));
  }

  // The killed worker's completion, arriving late, is refused.
  v1::CompleteTaskRequest late;
  late.set_key(victim.drape_key());
  late.set_token(victim.lease_token());
  late.mutable_result()->set_key(victim.drape_key());
  v1::CompleteTaskResponse response;
  EXPECT_EQ(clients_->queue->CompleteTask(Call(TestKeys::kWorker).get(), late, &response)
                .error_code(),
            grpc::StatusCode::FAILED_PRECONDITION);

  rescuer->Signal(SIGTERM);
  EXPECT_EQ(rescuer->Wait(), 0);
  coordinator->Signal(SIGTERM);
  EXPECT_EQ(coordinator->Wait(), 0);
  auto store = storage::AssetStore::Open(dir_ / "db", {.mode = storage::OpenMode::kReadOnly});
  ASSERT_TRUE(store.ok()) << store.status();
  const v1::Garment garment = SmallGarment();
  EXPECT_EQ((*store)
                ->ListClothingBasisVersions(
                    {"acme", garment_id, "M", garment.avatar_basis_id(), "linear"})
                ->size(),
            1u);
}

TEST_F(BuildFaultsTest, AKilledCoordinatorResumesTheBuildWithoutRedoingDoneTasks) {
  auto coordinator = StartCoordinator(0, /*lease_seconds=*/10);
  const std::string garment_id = Catalogue();
  auto worker = StartWorker("steady");
  const v1::Build build = SubmitSlowBuild(garment_id);
  const v1::GetBuildResponse before =
      WatchUntil(build.build_id(), [](const v1::Build& b) { return b.tasks_done() >= 2; });
  coordinator->Signal(SIGKILL);
  coordinator->Wait();

  const int port = port_;
  coordinator = StartCoordinator(port, /*lease_seconds=*/10);
  ASSERT_EQ(port_, port);
  // The same worker reconnects by itself and finishes the build.
  const v1::GetBuildResponse after = WatchUntil(build.build_id(), [](const v1::Build& b) {
    return b.phase() == v1::BUILD_SUCCEEDED || b.phase() == v1::BUILD_FAILED;
  });
  ASSERT_EQ(after.build().phase(), v1::BUILD_SUCCEEDED) << after.build().error();
  int done_before = 0;
  for (const v1::Task& task : before.tasks()) {
    if (task.phase() != v1::TASK_DONE) continue;
    ++done_before;
    for (const v1::Task& now : after.tasks()) {
      if (now.task_id() == task.task_id()) EXPECT_EQ(now.leases(), 1u) << now.task_id();
    }
  }
  EXPECT_GE(done_before, 2);
  worker->Signal(SIGTERM);
  EXPECT_EQ(worker->Wait(), 0);
}

}  // namespace
}  // namespace fitbase
