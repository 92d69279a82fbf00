// The distributed build in one process: a real coordinator server on 127.0.0.1 with a real
// RocksDB store, real drape workers, and raw WorkerQueue clients where a test must act as a
// worker that misbehaves. Faults across processes are in build_faults_test.
#include <limits>
#include <thread>

#include "core/file_util.h"
#include "core/test_support.h"
#include "fitbase/v1/clothing_basis.pb.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "services/build/coordinator_server.h"
#include "services/rpc/clock.h"
#include "services/rpc/tls_credentials.h"
#include "storage/asset_store.h"
#include "tests/build_cluster.h"
#include "tests/stub_workers.h"
#include "workers/drape_worker.h"

namespace fitbase {
namespace {

using ::testing::HasSubstr;

constexpr absl::Duration kLease = absl::Seconds(30);

class DistributedBuildTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(std::filesystem::exists(SmallCatalogue() / "ready"))
        << "run through ctest: the small_catalogue fixture makes " << SmallCatalogue();
    db_ = core::ProcessTempDir() / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::filesystem::remove_all(db_);
    Start();
    garment_ = SmallGarment();
    PublishSmallBasis(*clients_);
    ASSERT_TRUE(server_->store()
                    .PutGarment("acme", garment_.id(), proto::SerializeDeterministically(garment_))
                    .ok());
  }
  void TearDown() override {
    StopWorkers();
    if (server_ != nullptr) server_->Shutdown(absl::Seconds(1));
  }

  void Start(int max_message_bytes = 64 << 20,
             std::shared_ptr<grpc::ServerCredentials> credentials = nullptr) {
    build::CoordinatorServerOptions options;
    options.db = db_;
    options.listen = "127.0.0.1:0";
    options.data_dir = core::TestDataDir();
    options.keys = TestKeys::Registry();
    options.coordinator.clock = &clock_;
    options.coordinator.lease = kLease;
    options.coordinator.max_attempts = 3;
    options.max_message_bytes = max_message_bytes;
    options.credentials = std::move(credentials);
    auto server = build::CoordinatorServer::Start(std::move(options));
    ASSERT_TRUE(server.ok()) << server.status();
    server_ = *std::move(server);
    address_ = absl::StrCat("127.0.0.1:", server_->port());
    if (!tls_) clients_ = std::make_unique<Clients>(address_);
  }

  void Restart() {
    StopWorkers();
    server_->Shutdown(absl::Seconds(1));
    server_.reset();
    Start();
  }

  void StartWorkers(int count,
                    std::shared_ptr<grpc::ChannelCredentials> credentials = nullptr) {
    for (int i = 0; i < count; ++i) {
      workers::DrapeWorkerOptions options;
      options.credentials = credentials;
      options.tls_target_name = credentials ? "fitbase-coordinator" : "";
      options.coordinator = address_;
      options.api_key = TestKeys::kWorker;
      options.name = absl::StrCat("w", i);
      options.lease_wait = absl::Seconds(2);
      workers_.push_back(std::make_unique<workers::DrapeWorker>(options));
      threads_.emplace_back([w = workers_.back().get()] { w->Run(); });
    }
  }

  void StopWorkers() {
    for (auto& worker : workers_) worker->Drain();
    for (std::thread& thread : threads_) thread.join();
    threads_.clear();
    workers_.clear();
  }

  v1::Build Submit(const v1::SubmitBuildRequest& request) {
    v1::Build build;
    const grpc::Status status =
        clients_->coordinator->SubmitBuild(Call(TestKeys::kAdmin).get(), request, &build);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return build;
  }

  v1::GetBuildResponse Get(const std::string& build_id) {
    v1::GetBuildRequest request;
    request.set_build_id(build_id);
    request.set_with_tasks(true);
    v1::GetBuildResponse response;
    EXPECT_TRUE(
        clients_->coordinator->GetBuild(Call(TestKeys::kAdmin).get(), request, &response).ok());
    return response;
  }

  v1::LeaseTaskResponse Lease(int wait_ms = 0) {
    v1::LeaseTaskRequest request;
    request.set_worker("raw");
    request.set_wait_ms(wait_ms);
    v1::LeaseTaskResponse response;
    const grpc::Status status =
        clients_->queue->LeaseTask(Call(TestKeys::kWorker).get(), request, &response);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return response;
  }

  grpc::Status Complete(const v1::Lease& lease, uint64_t token) {
    v1::CompleteTaskRequest request;
    request.set_key(lease.key());
    request.set_token(token);
    request.mutable_result()->set_key(lease.key());
    request.mutable_result()->mutable_positions()->Resize(
        3 * static_cast<int>(garment_.template_mesh().vertex_count()), 0.0f);
    v1::CompleteTaskResponse response;
    return clients_->queue->CompleteTask(Call(TestKeys::kWorker).get(), request, &response);
  }

  grpc::Status Fail(const v1::Lease& lease, const std::string& error, bool returned = false) {
    v1::FailTaskRequest request;
    request.set_key(lease.key());
    request.set_token(lease.token());
    request.set_error(error);
    request.set_returned(returned);
    v1::FailTaskResponse response;
    return clients_->queue->FailTask(Call(TestKeys::kWorker).get(), request, &response);
  }

  storage::ClothingBasisKey MKey() const {
    return {"acme", garment_.id(), "M", garment_.avatar_basis_id(), "linear"};
  }

  rpc::ManualClock clock_{absl::FromUnixSeconds(1800000000)};
  bool tls_ = false;  // Plaintext clients_ only talk to a plaintext server.
  std::filesystem::path db_;
  std::unique_ptr<build::CoordinatorServer> server_;
  std::string address_;
  std::unique_ptr<Clients> clients_;
  v1::Garment garment_;
  std::vector<std::unique_ptr<workers::DrapeWorker>> workers_;
  std::vector<std::thread> threads_;
};

TEST_F(DistributedBuildTest, PublishesTheBytesOfTheLocalBuild) {
  StartWorkers(2);
  const v1::Build submitted = Submit(SmallBuild(garment_.id()));
  EXPECT_EQ(submitted.tasks_total(), 5u);
  const v1::Build done = WatchToEnd(*clients_, submitted.build_id());
  ASSERT_EQ(done.phase(), v1::BUILD_SUCCEEDED) << done.error();
  ASSERT_EQ(done.published_size(), 1);
  EXPECT_EQ(done.published(0).version(), 1u);
  auto stored = server_->store().GetCurrentClothingBasis(MKey());
  ASSERT_TRUE(stored.ok()) << stored.status();
  // `fitbase clothing build` of the same garment, size, method and schedule (the fixture).
  EXPECT_EQ(stored->bytes, *core::ReadFileToString(SmallCatalogue() / "M-linear.fbc"));
  EXPECT_EQ(done.published(0).clothing_basis_id(), stored->content_id);
}

TEST_F(DistributedBuildTest, AKernelBuildDrapesTheSampledBodiesToo) {
  StartWorkers(2);
  v1::SubmitBuildRequest request = SmallBuild(garment_.id());
  request.mutable_request()->add_methods("kernel");
  request.mutable_request()->set_sampled_drapes(3);
  const v1::Build submitted = Submit(request);
  EXPECT_EQ(submitted.tasks_total(), 5u + 3u);
  EXPECT_EQ(submitted.request().sample_seed(), 1u);
  const v1::Build done = WatchToEnd(*clients_, submitted.build_id());
  ASSERT_EQ(done.phase(), v1::BUILD_SUCCEEDED) << done.error();
  ASSERT_EQ(done.published_size(), 2);
  // The linear basis does not depend on the samples: the bytes of a linear-only build.
  auto linear = server_->store().GetCurrentClothingBasis(MKey());
  ASSERT_TRUE(linear.ok()) << linear.status();
  EXPECT_EQ(linear->bytes, *core::ReadFileToString(SmallCatalogue() / "M-linear.fbc"));
  storage::ClothingBasisKey kernel_key = MKey();
  kernel_key.method = "kernel";
  auto kernel = server_->store().GetCurrentClothingBasis(kernel_key);
  ASSERT_TRUE(kernel.ok()) << kernel.status();
  v1::ClothingBasis basis;
  ASSERT_TRUE(basis.ParseFromString(kernel->bytes));
  EXPECT_EQ(basis.provenance().sampled_drapes(), 3u);
  EXPECT_EQ(basis.provenance().examples_size(), 8);
  EXPECT_GE(basis.kernel().output_count(), 1u);
}

TEST_F(DistributedBuildTest, ResubmittingAFinishedBuildIsAllCacheHits) {
  StartWorkers(1);
  const v1::Build first = WatchToEnd(*clients_, Submit(SmallBuild(garment_.id())).build_id());
  ASSERT_EQ(first.phase(), v1::BUILD_SUCCEEDED);
  StopWorkers();  // Nothing may need a worker now.
  const v1::Build again = Submit(SmallBuild(garment_.id()));
  EXPECT_EQ(again.cache_hits(), 5u);
  EXPECT_EQ(again.tasks_done(), 5u);
  const v1::Build done = WatchToEnd(*clients_, again.build_id());
  ASSERT_EQ(done.phase(), v1::BUILD_SUCCEEDED);
  EXPECT_EQ(done.published(0).version(), 1u);  // The same content: published once.
  EXPECT_EQ(server_->store().ListClothingBasisVersions(MKey())->size(), 1u);
}

TEST_F(DistributedBuildTest, IdenticalTasksInFlightRunOnce) {
  const v1::Build a = Submit(SmallBuild(garment_.id()));
  const v1::Build b = Submit(SmallBuild(garment_.id()));
  EXPECT_EQ(b.cache_hits(), 5u);  // Every task joins a's execution.
  StartWorkers(2);
  EXPECT_EQ(WatchToEnd(*clients_, a.build_id()).phase(), v1::BUILD_SUCCEEDED);
  EXPECT_EQ(WatchToEnd(*clients_, b.build_id()).phase(), v1::BUILD_SUCCEEDED);
  const v1::GetBuildResponse state = Get(a.build_id());
  for (const v1::Task& task : state.tasks()) EXPECT_EQ(task.leases(), 1u);
  EXPECT_EQ(workers_[0]->completed() + workers_[1]->completed(), 5);
}

TEST_F(DistributedBuildTest, ExpiredLeaseIsReleasedAndItsLateCompletionRefused) {
  const v1::Build build = Submit(SmallBuild(garment_.id()));
  const v1::LeaseTaskResponse first = Lease();
  ASSERT_TRUE(first.has_lease());
  EXPECT_EQ(first.lease().attempt(), 1u);
  EXPECT_EQ(first.spec().key(), first.lease().key());
  clock_.Advance(kLease + absl::Seconds(1));
  EXPECT_EQ(server_->coordinator().ReapExpiredLeases(), 1);
  // Requeued at the back: the other four tasks come first.
  v1::LeaseTaskResponse second;
  for (int i = 0; i < 5; ++i) {
    second = Lease();
    ASSERT_TRUE(second.has_lease());
    if (second.lease().key() == first.lease().key()) break;
  }
  ASSERT_EQ(second.lease().key(), first.lease().key());
  EXPECT_EQ(second.lease().attempt(), 2u);
  EXPECT_GT(second.lease().token(), first.lease().token());
  const grpc::Status late = Complete(first.lease(), first.lease().token());
  EXPECT_EQ(late.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_THAT(late.error_message(), HasSubstr("stale"));
  v1::HeartbeatRequest heartbeat;
  heartbeat.set_key(first.lease().key());
  heartbeat.set_token(first.lease().token());
  v1::HeartbeatResponse beat;
  EXPECT_EQ(clients_->queue->Heartbeat(Call(TestKeys::kWorker).get(), heartbeat, &beat)
                .error_code(),
            grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_TRUE(Complete(second.lease(), second.lease().token()).ok());
  // Idempotent for the lease that completed it; still refused for the stale one.
  EXPECT_TRUE(Complete(second.lease(), second.lease().token()).ok());
  EXPECT_EQ(Complete(first.lease(), first.lease().token()).error_code(),
            grpc::StatusCode::FAILED_PRECONDITION);
  const v1::GetBuildResponse state = Get(build.build_id());
  for (const v1::Task& task : state.tasks()) {
    if (task.drape_key() != first.lease().key()) continue;
    EXPECT_EQ(task.phase(), v1::TASK_DONE);
    EXPECT_EQ(task.attempts(), 1u);
    EXPECT_EQ(task.leases(), 2u);
    EXPECT_THAT(task.error(), HasSubstr("expired"));
  }
}

TEST_F(DistributedBuildTest, HeartbeatsKeepALeaseAlive) {
  Submit(SmallBuild(garment_.id()));
  const v1::LeaseTaskResponse leased = Lease();
  v1::HeartbeatRequest heartbeat;
  heartbeat.set_key(leased.lease().key());
  heartbeat.set_token(leased.lease().token());
  for (int i = 0; i < 3; ++i) {
    clock_.Advance(kLease - absl::Seconds(1));
    v1::HeartbeatResponse beat;
    ASSERT_TRUE(clients_->queue->Heartbeat(Call(TestKeys::kWorker).get(), heartbeat, &beat).ok());
    EXPECT_EQ(server_->coordinator().ReapExpiredLeases(), 0);
  }
  EXPECT_TRUE(Complete(leased.lease(), leased.lease().token()).ok());
}

TEST_F(DistributedBuildTest, ATaskFailingEveryTimeFailsTheBuildAfterKAttempts) {
  const v1::Build build = Submit(SmallBuild(garment_.id()));
  std::string key;
  for (int attempt = 1; attempt <= 3; ++attempt) {
    v1::LeaseTaskResponse leased;
    do {  // Leases of the other tasks are simply held; only `key` fails.
      leased = Lease();
      ASSERT_TRUE(leased.has_lease());
    } while (!key.empty() && leased.lease().key() != key);
    key = leased.lease().key();
    EXPECT_EQ(leased.lease().attempt(), static_cast<uint32_t>(attempt));
    ASSERT_TRUE(Fail(leased.lease(), "solver diverged at step 7").ok());
  }
  const v1::GetBuildResponse failed = Get(build.build_id());
  EXPECT_EQ(failed.build().phase(), v1::BUILD_FAILED);
  EXPECT_THAT(failed.build().error(), HasSubstr("failed 3 times"));
  EXPECT_THAT(failed.build().error(), HasSubstr("solver diverged at step 7"));
  for (const v1::Task& task : failed.tasks()) {
    EXPECT_EQ(task.phase(), task.drape_key() == key ? v1::TASK_FAILED : v1::TASK_CANCELLED);
  }
  EXPECT_FALSE(Lease().has_lease());  // Nothing of the failed build is left to run.
  EXPECT_TRUE(server_->store().ListClothingBasisVersions(MKey())->empty());
}

TEST_F(DistributedBuildTest, AReturnedLeaseCountsNoAttempt) {
  const v1::Build build = Submit(SmallBuild(garment_.id()));
  const v1::LeaseTaskResponse leased = Lease();
  ASSERT_TRUE(Fail(leased.lease(), "worker shutting down", /*returned=*/true).ok());
  const v1::LeaseTaskResponse again = Lease();
  EXPECT_EQ(again.lease().key(), leased.lease().key());  // Back at the front.
  EXPECT_EQ(again.lease().attempt(), 1u);
}

// The coordinator at scale, smaller: many builds queued, then many workers leasing at once
// over gRPC (fitbase_build_bench runs 10,000 tasks and 64 workers).
TEST_F(DistributedBuildTest, ManyWorkersLeasingAtOnceCompleteEveryTaskExactlyOnce) {
  constexpr int kBuilds = 20;
  std::vector<v1::Build> builds;
  for (int i = 0; i < kBuilds; ++i) {
    v1::SubmitBuildRequest request = SmallBuild(garment_.id());
    // Another schedule is another drape key: every task is a drape of its own.
    request.mutable_request()->set_relax_steps(static_cast<uint32_t>(1 + i));
    builds.push_back(Submit(request));
    ASSERT_EQ(builds.back().cache_hits(), 0u);
  }
  StubWorkers workers(address_, TestKeys::kWorker, 16);
  for (const v1::Build& build : builds) {
    build::BuildSnapshot snapshot;
    while (snapshot.build.tasks_done() < build.tasks_total() &&
           snapshot.build.phase() != v1::BUILD_FAILED) {
      auto next = server_->coordinator().WaitForBuild("acme", build.build_id(),
                                                      snapshot.revision,
                                                      absl::Now() + absl::Seconds(120));
      ASSERT_TRUE(next.ok()) << next.status();
      snapshot = *std::move(next);
    }
    ASSERT_NE(snapshot.build.phase(), v1::BUILD_FAILED) << snapshot.build.error();
  }
  const StubWorkers::Report report = workers.Stop();
  EXPECT_EQ(report.failed_calls, 0) << report.first_failure;
  EXPECT_EQ(report.concurrent_double_leases, 0);
  EXPECT_EQ(report.foreign_tokens_accepted, 0);
  EXPECT_EQ(report.completed, 5 * kBuilds);
  EXPECT_EQ(report.completions.size(), 5u * kBuilds);
  for (const auto& [key, times] : report.completions) EXPECT_EQ(times, 1) << key;
  for (const v1::Build& build : builds) {
    const v1::GetBuildResponse state = Get(build.build_id());
    for (const v1::Task& task : state.tasks()) {
      EXPECT_EQ(task.phase(), v1::TASK_DONE) << task.task_id();
      EXPECT_EQ(task.leases(), 1u) << task.task_id();
      EXPECT_TRUE(report.completions.contains(task.drape_key()));
      EXPECT_TRUE(server_->store().GetDrapeResult(task.drape_key()).ok());
    }
  }
}

TEST_F(DistributedBuildTest, ARestartedCoordinatorResumesWithoutRedoingDoneTasks) {
  const v1::Build build = Submit(SmallBuild(garment_.id()));
  const v1::LeaseTaskResponse done = Lease();
  ASSERT_TRUE(Complete(done.lease(), done.lease().token()).ok());
  const v1::LeaseTaskResponse running = Lease();
  Restart();
  const v1::GetBuildResponse resumed = Get(build.build_id());
  EXPECT_EQ(resumed.build().tasks_done(), 1u);
  // The worker that was draping across the restart completes under its old lease.
  EXPECT_TRUE(Complete(running.lease(), running.lease().token()).ok());
  int leased = 0;
  for (v1::LeaseTaskResponse next = Lease(); next.has_lease(); next = Lease()) {
    EXPECT_NE(next.lease().key(), done.lease().key());
    EXPECT_NE(next.lease().key(), running.lease().key());
    EXPECT_GT(next.lease().token(), running.lease().token());
    ++leased;
  }
  EXPECT_EQ(leased, 3);
}

TEST_F(DistributedBuildTest, KeysAndRolesAreEnforced) {
  v1::Build build;
  const v1::SubmitBuildRequest request = SmallBuild(garment_.id());
  EXPECT_EQ(clients_->coordinator->SubmitBuild(Call("").get(), request, &build).error_code(),
            grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(
      clients_->coordinator->SubmitBuild(Call("fb_not_a_key").get(), request, &build).error_code(),
      grpc::StatusCode::UNAUTHENTICATED);
  for (const char* key : {TestKeys::kCustomer, TestKeys::kWorker}) {
    EXPECT_EQ(clients_->coordinator->SubmitBuild(Call(key).get(), request, &build).error_code(),
              grpc::StatusCode::PERMISSION_DENIED);
  }
  v1::LeaseTaskRequest lease;
  lease.set_worker("intruder");
  v1::LeaseTaskResponse leased;
  EXPECT_EQ(clients_->queue->LeaseTask(Call(TestKeys::kIngestion).get(), lease, &leased)
                .error_code(),
            grpc::StatusCode::PERMISSION_DENIED);
}

// Every record the RPCs could have written.
std::string StoreState(storage::AssetStore& store) {
  std::string state;
  for (const char* tenant : {"acme", "rival"}) {
    const std::vector<std::string> ids = *store.ListGarmentIds(tenant);
    for (const std::string& id : ids) absl::StrAppend(&state, id, ";");
  }
  const std::vector<storage::JobRecord> builds = *store.ListBuilds();
  for (const storage::JobRecord& build : builds) {
    absl::StrAppend(&state, build.id, build.bytes);
    const std::vector<storage::JobRecord> tasks = *store.ListTasks(build.id);
    for (const storage::JobRecord& task : tasks) absl::StrAppend(&state, task.id, task.bytes);
  }
  return state;
}

TEST_F(DistributedBuildTest, BadInputGetsTheRightCodeAndLeavesTheStoreUnchanged) {
  const v1::Build build = Submit(SmallBuild(garment_.id()));
  const v1::LeaseTaskResponse leased = Lease();
  // Reopened with a small message limit.
  server_->Shutdown(absl::Seconds(1));
  server_.reset();
  Start(/*max_message_bytes=*/1 << 20);
  const std::string before = StoreState(server_->store());
  v1::Build ignored;

  v1::SubmitBuildRequest unknown = SmallBuild("no-such-garment");
  EXPECT_EQ(clients_->coordinator->SubmitBuild(Call(TestKeys::kAdmin).get(), unknown, &ignored)
                .error_code(),
            grpc::StatusCode::NOT_FOUND);
  v1::SubmitBuildRequest bad_size = SmallBuild(garment_.id());
  bad_size.mutable_request()->set_sizes(0, "XXXL");
  EXPECT_EQ(clients_->coordinator->SubmitBuild(Call(TestKeys::kAdmin).get(), bad_size, &ignored)
                .error_code(),
            grpc::StatusCode::NOT_FOUND);
  v1::SubmitBuildRequest bad_method = SmallBuild(garment_.id());
  bad_method.mutable_request()->set_methods(0, "cubic");
  EXPECT_EQ(clients_->coordinator->SubmitBuild(Call(TestKeys::kAdmin).get(), bad_method, &ignored)
                .error_code(),
            grpc::StatusCode::INVALID_ARGUMENT);
  v1::SubmitBuildRequest kernel_unsampled = SmallBuild(garment_.id());
  kernel_unsampled.mutable_request()->set_methods(0, "kernel");
  EXPECT_EQ(clients_->coordinator
                ->SubmitBuild(Call(TestKeys::kAdmin).get(), kernel_unsampled, &ignored)
                .error_code(),
            grpc::StatusCode::INVALID_ARGUMENT);
  v1::SubmitBuildRequest too_many_samples = kernel_unsampled;
  too_many_samples.mutable_request()->set_sampled_drapes(1u << 30);
  EXPECT_EQ(clients_->coordinator
                ->SubmitBuild(Call(TestKeys::kAdmin).get(), too_many_samples, &ignored)
                .error_code(),
            grpc::StatusCode::INVALID_ARGUMENT);
  v1::SubmitBuildRequest other_basis = SmallBuild(garment_.id());
  other_basis.mutable_request()->set_avatar_basis_id("another-basis");
  EXPECT_EQ(clients_->coordinator->SubmitBuild(Call(TestKeys::kAdmin).get(), other_basis, &ignored)
                .error_code(),
            grpc::StatusCode::FAILED_PRECONDITION);

  // Another tenant sees neither the garment nor the build.
  EXPECT_EQ(clients_->coordinator
                ->SubmitBuild(Call(TestKeys::kRival).get(), SmallBuild(garment_.id()), &ignored)
                .error_code(),
            grpc::StatusCode::NOT_FOUND);
  v1::GetBuildRequest get;
  get.set_build_id(build.build_id());
  v1::GetBuildResponse got;
  EXPECT_EQ(clients_->coordinator->GetBuild(Call(TestKeys::kRival).get(), get, &got).error_code(),
            grpc::StatusCode::NOT_FOUND);
  v1::CancelBuildRequest cancel;
  cancel.set_build_id(build.build_id());
  EXPECT_EQ(clients_->coordinator->CancelBuild(Call(TestKeys::kRival).get(), cancel, &ignored)
                .error_code(),
            grpc::StatusCode::NOT_FOUND);

  v1::UploadGarmentRequest upload;
  upload.set_avatar_basis_id(garment_.avatar_basis_id());
  upload.add_sizes("M");
  upload.mutable_obj()->set_name("broken.obj");
  upload.mutable_obj()->set_content("v 0 1\nf 1 2 3\n");
  v1::UploadGarmentResponse uploaded;
  grpc::Status status =
      clients_->catalog->UploadGarment(Call(TestKeys::kAdmin).get(), upload, &uploaded);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("broken.obj"));
  upload.set_avatar_basis_id("no-such-basis");
  EXPECT_EQ(clients_->catalog->UploadGarment(Call(TestKeys::kAdmin).get(), upload, &uploaded)
                .error_code(),
            grpc::StatusCode::NOT_FOUND);
  upload.mutable_obj()->set_content(std::string(2 << 20, 'v'));
  EXPECT_EQ(clients_->catalog->UploadGarment(Call(TestKeys::kAdmin).get(), upload, &uploaded)
                .error_code(),
            grpc::StatusCode::RESOURCE_EXHAUSTED);

  EXPECT_EQ(StoreState(server_->store()), before);

  // A result of the wrong size is refused, stored nowhere, and counts as a failed attempt.
  v1::CompleteTaskRequest complete;
  complete.set_key(leased.lease().key());
  complete.set_token(leased.lease().token());
  complete.mutable_result()->set_key(leased.lease().key());
  complete.mutable_result()->add_positions(0.0f);
  v1::CompleteTaskResponse completed;
  EXPECT_EQ(clients_->queue->CompleteTask(Call(TestKeys::kWorker).get(), complete, &completed)
                .error_code(),
            grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_FALSE(server_->store().GetDrapeResult(leased.lease().key()).ok());

  const v1::GetBuildResponse state = Get(build.build_id());
  for (const v1::Task& task : state.tasks()) {
    if (task.drape_key() == leased.lease().key()) {
      EXPECT_THAT(task.error(), HasSubstr("coordinates"));
      EXPECT_EQ(task.attempts(), 1u);
    }
  }
  // So is a result with a position that is not finite.
  const v1::LeaseTaskResponse next = Lease();
  ASSERT_TRUE(next.has_lease());
  complete.set_key(next.lease().key());
  complete.set_token(next.lease().token());
  complete.mutable_result()->set_key(next.lease().key());
  complete.mutable_result()->mutable_positions()->Resize(
      3 * static_cast<int>(garment_.template_mesh().vertex_count()), 0.0f);
  complete.mutable_result()->set_positions(4, std::numeric_limits<float>::infinity());
  const grpc::Status not_finite =
      clients_->queue->CompleteTask(Call(TestKeys::kWorker).get(), complete, &completed);
  EXPECT_EQ(not_finite.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(not_finite.error_message(), HasSubstr("non-finite"));
  EXPECT_FALSE(server_->store().GetDrapeResult(next.lease().key()).ok());
  EXPECT_EQ(*server_->store().ListGarmentIds("acme"), std::vector<std::string>{garment_.id()});
  EXPECT_TRUE(server_->store().ListGarmentIds("rival")->empty());
  EXPECT_EQ(server_->store().ListBuilds()->size(), 1u);
}

TEST_F(DistributedBuildTest, UploadImportsTheGarmentOnTheServer) {
  const std::filesystem::path dir = core::TestDataDir() / "clothes" / "female_sportsuit01";
  v1::UploadGarmentRequest upload;
  upload.set_avatar_basis_id(garment_.avatar_basis_id());
  upload.add_sizes("M");
  upload.add_sizes("XL");
  upload.mutable_mhclo()->set_name((dir / "female_sportsuit01.mhclo").string());
  upload.mutable_mhclo()->set_content(*core::ReadFileToString(dir / "female_sportsuit01.mhclo"));
  upload.mutable_obj()->set_name("female_sportsuit01.obj");
  upload.mutable_obj()->set_content(*core::ReadFileToString(dir / "female_sportsuit01.obj"));
  v1::UploadGarmentResponse uploaded;
  const grpc::Status status =
      clients_->catalog->UploadGarment(Call(TestKeys::kRival).get(), upload, &uploaded);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(uploaded.garment_id(), garment_.id());  // The CLI's import of the same files.
  EXPECT_TRUE(uploaded.created());
  EXPECT_EQ(*server_->store().ListGarmentIds("rival"), std::vector<std::string>{garment_.id()});

  // Declared cuffs make another garment, which keeps them for its drapes.
  upload.mutable_cuffs()->set_legs(true);
  v1::UploadGarmentResponse cuffed;
  ASSERT_TRUE(clients_->catalog->UploadGarment(Call(TestKeys::kRival).get(), upload, &cuffed).ok());
  EXPECT_NE(cuffed.garment_id(), garment_.id());
  EXPECT_TRUE(cuffed.created());
  absl::StatusOr<std::string> stored = server_->store().GetGarment("rival", cuffed.garment_id());
  ASSERT_TRUE(stored.ok()) << stored.status();
  v1::Garment garment;
  ASSERT_TRUE(garment.ParseFromString(*stored));
  EXPECT_TRUE(garment.cuffs().legs());
  EXPECT_FALSE(garment.cuffs().sleeves());
}

TEST_F(DistributedBuildTest, AdminsCheckpointTheStoreAsAReadOnlyReplica) {
  v1::CreateCheckpointRequest request;
  request.set_name("nightly");
  v1::CreateCheckpointResponse response;
  EXPECT_EQ(clients_->catalog->CreateCheckpoint(Call(TestKeys::kIngestion).get(), request,
                                                &response)
                .error_code(),
            grpc::StatusCode::PERMISSION_DENIED);
  for (const char* name : {"", "../escape", ".hidden", "a/b"}) {
    request.set_name(name);
    EXPECT_EQ(clients_->catalog->CreateCheckpoint(Call(TestKeys::kAdmin).get(), request,
                                                  &response)
                  .error_code(),
              grpc::StatusCode::INVALID_ARGUMENT)
        << name;
  }
  request.set_name("nightly");
  const grpc::Status status =
      clients_->catalog->CreateCheckpoint(Call(TestKeys::kAdmin).get(), request, &response);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(response.path(), (db_.string() + "-checkpoints/nightly"));
  EXPECT_EQ(clients_->catalog->CreateCheckpoint(Call(TestKeys::kAdmin).get(), request, &response)
                .error_code(),
            grpc::StatusCode::ALREADY_EXISTS);
  auto replica = storage::AssetStore::Open(response.path(), {.mode = storage::OpenMode::kReadOnly});
  ASSERT_TRUE(replica.ok()) << replica.status();
  EXPECT_EQ(*(*replica)->ListGarmentIds("acme"), std::vector<std::string>{garment_.id()});
}

std::filesystem::path Tls(const std::string& name) {
  return std::filesystem::path(FITBASE_SOURCE_DIR) / "tests/testdata/tls" / name;
}

TEST_F(DistributedBuildTest, WithMutualTlsOnlyCertifiedWorkersConnect) {
  const v1::Build build = Submit(SmallBuild(garment_.id()));
  server_->Shutdown(absl::Seconds(1));
  server_.reset();
  auto server_credentials = rpc::TlsServerCredentials(
      {.cert = Tls("server.pem"), .key = Tls("server.key"), .ca = Tls("ca.pem")});
  ASSERT_TRUE(server_credentials.ok()) << server_credentials.status();
  tls_ = true;
  Start(64 << 20, *server_credentials);

  auto connect = [&](const rpc::TlsFiles& files) {
    grpc::ChannelArguments arguments;
    arguments.SetSslTargetNameOverride("fitbase-coordinator");
    return v1::WorkerQueue::NewStub(grpc::CreateCustomChannel(
        address_, *rpc::TlsChannelCredentials(files), arguments));
  };
  v1::LeaseTaskRequest lease;
  lease.set_worker("probe");
  v1::LeaseTaskResponse leased;
  // No client certificate, one from another CA, and plaintext are all turned away.
  for (const rpc::TlsFiles& files :
       {rpc::TlsFiles{.cert = {}, .key = {}, .ca = Tls("ca.pem")},
        rpc::TlsFiles{.cert = Tls("intruder.pem"), .key = Tls("intruder.key"),
                           .ca = Tls("ca.pem")}}) {
    EXPECT_EQ(connect(files)->LeaseTask(Call(TestKeys::kWorker, 5).get(), lease, &leased)
                  .error_code(),
              grpc::StatusCode::UNAVAILABLE);
  }
  EXPECT_EQ(v1::WorkerQueue::NewStub(rpc::OpenChannel(address_))
                ->LeaseTask(Call(TestKeys::kWorker, 5).get(), lease, &leased)
                .error_code(),
            grpc::StatusCode::UNAVAILABLE);

  auto worker_credentials = rpc::TlsChannelCredentials(
      {.cert = Tls("worker.pem"), .key = Tls("worker.key"), .ca = Tls("ca.pem")});
  ASSERT_TRUE(worker_credentials.ok()) << worker_credentials.status();
  StartWorkers(2, *worker_credentials);
  // Followed in process: the test's plaintext clients cannot reach this server.
  build::BuildSnapshot snapshot;
  do {
    auto next = server_->coordinator().WaitForBuild("acme", build.build_id(), snapshot.revision,
                                                    absl::Now() + absl::Seconds(120));
    ASSERT_TRUE(next.ok()) << next.status();
    snapshot = *std::move(next);
  } while (snapshot.build.phase() == v1::BUILD_QUEUED ||
           snapshot.build.phase() == v1::BUILD_RUNNING ||
           snapshot.build.phase() == v1::BUILD_ASSEMBLING);
  EXPECT_EQ(snapshot.build.phase(), v1::BUILD_SUCCEEDED) << snapshot.build.error();
}

}  // namespace
}  // namespace fitbase
