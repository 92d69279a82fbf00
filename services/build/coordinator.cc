#include "services/build/coordinator.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/strip.h"
#include "clothing/clothing_model.h"
#include "core/log_line.h"
#include "core/status_macros.h"
#include "proto/message_file.h"
#include "storage/asset_write.h"
#include "workers/drape_task_spec.h"

namespace fitbase::build {
namespace {

constexpr char kBuildIdPrefix[] = "build-";

bool IsTerminal(v1::BuildPhase phase) {
  return phase == v1::BUILD_SUCCEEDED || phase == v1::BUILD_FAILED ||
         phase == v1::BUILD_CANCELLED;
}

bool IsOpen(v1::TaskPhase phase) {
  return phase == v1::TASK_QUEUED || phase == v1::TASK_LEASED;
}

int64_t UnixMillis(absl::Time time) { return absl::ToUnixMillis(time); }

void ClearLease(v1::Task& task) {
  task.clear_worker();
  task.set_lease_expiry_unix_ms(0);
}

}  // namespace

Coordinator::Coordinator(storage::AssetStore* store, const CoordinatorOptions& options)
    : store_(store),
      options_(options),
      clock_(options.clock ? options.clock : &real_clock_),
      plans_(options.cached_plans) {}

absl::StatusOr<std::unique_ptr<Coordinator>> Coordinator::Open(
    storage::AssetStore* store, const CoordinatorOptions& options) {
  if (options.lease <= absl::ZeroDuration() || options.max_attempts == 0 ||
      options.assembly_threads < 1) {
    return absl::InvalidArgumentError(
        "the lease, max_attempts and assembly_threads must be positive");
  }
  std::unique_ptr<Coordinator> coordinator(new Coordinator(store, options));
  RETURN_IF_ERROR(coordinator->Recover());
  coordinator->assembler_ = std::thread([c = coordinator.get()] { c->RunAssembler(); });
  return coordinator;
}

Coordinator::~Coordinator() {
  Shutdown();
  if (assembler_.joinable()) assembler_.join();
}

void Coordinator::Shutdown() {
  std::lock_guard lock(mutex_);
  shutdown_ = true;
  queue_changed_.notify_all();
  builds_changed_.notify_all();
}

absl::Status Coordinator::CheckUsableLocked() const {
  if (!broken_.ok()) {
    return absl::UnavailableError(
        absl::StrCat("the coordinator stopped after a failed store write (", broken_.message(),
                     "); it recovers on restart"));
  }
  return absl::OkStatus();
}

absl::Status Coordinator::CommitLocked(const storage::AssetWrite& write, bool sync) {
  absl::Status status = store_->Commit(write, sync);
  if (!status.ok()) {
    broken_ = status;
    core::LogLine("store_write_failed").Add("error", status.ToString());
    queue_changed_.notify_all();
    builds_changed_.notify_all();
    return CheckUsableLocked();
  }
  return absl::OkStatus();
}

absl::StatusOr<bool> Coordinator::HasDrapeResult(absl::string_view key) const {
  absl::StatusOr<std::string> stored = store_->GetDrapeResult(key);
  if (stored.ok()) return true;
  if (absl::IsNotFound(stored.status())) return false;
  return stored.status();
}

void Coordinator::TouchLocked(BuildRun& run) {
  run.revision = ++revision_;
  builds_changed_.notify_all();
}

void Coordinator::PutRunLocked(const BuildRun& run, storage::AssetWrite& write) const {
  write.PutBuild(run.build.build_id(), proto::SerializeDeterministically(run.build));
}

std::vector<Coordinator::BuildRun*> Coordinator::UpdateWaitersLocked(
    const std::vector<Waiter>& waiters, absl::FunctionRef<void(const Waiter&, v1::Task&)> update,
    storage::AssetWrite& write) {
  std::vector<BuildRun*> runs;
  for (const Waiter& waiter : waiters) {
    BuildRun& run = *builds_.at(waiter.build_id);
    v1::Task& task = run.tasks.at(waiter.task_id);
    update(waiter, task);
    write.PutTask(waiter.build_id, waiter.task_id, proto::SerializeDeterministically(task));
    MaybeAssembleLocked(run);
    PutRunLocked(run, write);
    TouchLocked(run);
    runs.push_back(&run);
  }
  return runs;
}

Coordinator::BuildRun* Coordinator::FindBuildLocked(absl::string_view tenant,
                                                    absl::string_view build_id) const {
  auto it = builds_.find(std::string(build_id));
  if (it == builds_.end() || it->second->build.tenant() != tenant) return nullptr;
  return it->second.get();
}

bool Coordinator::JoinExecutionLocked(BuildRun& run, const v1::Task& task,
                                      int64_t vertex_count) {
  auto [it, created] = executions_.try_emplace(task.drape_key());
  Execution& execution = it->second;
  if (created) {
    execution.key = task.drape_key();
    execution.vertex_count = vertex_count;
    queue_.push_back(execution.key);
    queue_changed_.notify_one();
  }
  execution.attempts = std::max(execution.attempts, task.attempts());
  execution.waiters.push_back({run.build.build_id(), task.task_id()});
  return !created;
}

void Coordinator::MaybeAssembleLocked(BuildRun& run) {
  uint32_t done = 0;
  uint32_t running = 0;
  for (const auto& [id, task] : run.tasks) {
    done += task.phase() == v1::TASK_DONE;
    running += task.phase() == v1::TASK_LEASED;
  }
  run.build.set_tasks_done(done);
  run.build.set_tasks_running(running);
  if (IsTerminal(run.build.phase()) || run.build.phase() == v1::BUILD_ASSEMBLING) return;
  if (running > 0 || done > 0) run.build.set_phase(v1::BUILD_RUNNING);
  if (done == run.build.tasks_total()) {
    run.build.set_phase(v1::BUILD_ASSEMBLING);
    assembly_queue_.push_back(run.build.build_id());
    builds_changed_.notify_all();
  }
}

absl::StatusOr<v1::Build> Coordinator::Submit(absl::string_view tenant,
                                              const v1::BuildRequest& request) {
  {
    std::lock_guard lock(mutex_);
    RETURN_IF_ERROR(CheckUsableLocked());
  }
  ASSIGN_OR_RETURN(std::unique_ptr<const BuildPlan> planned, PlanBuild(*store_, tenant, request));
  std::shared_ptr<const BuildPlan> plan = std::move(planned);
  // Looked up before taking the lock: reading results must not stall the workers' calls.
  std::set<std::string> stored;
  for (const BuildPlan::Size& size : plan->sizes) {
    for (const workers::DrapeTask& task : size.plan.tasks) {
      ASSIGN_OR_RETURN(bool has, HasDrapeResult(task.key));
      if (has) stored.insert(task.key);
    }
  }

  std::lock_guard lock(mutex_);
  RETURN_IF_ERROR(CheckUsableLocked());
  auto run = std::make_unique<BuildRun>();
  v1::Build& build = run->build;
  build.set_build_id(absl::StrFormat("%s%06d", kBuildIdPrefix, next_build_number_));
  build.set_tenant(std::string(tenant));
  *build.mutable_request() = plan->request;
  build.set_phase(v1::BUILD_QUEUED);
  build.set_created_unix_ms(UnixMillis(Now()));
  std::vector<v1::Task*> to_run;
  for (const BuildPlan::Size& size : plan->sizes) {
    for (size_t i = 0; i < size.plan.tasks.size(); ++i) {
      const workers::DrapeTask& drape = size.plan.tasks[i];
      v1::Task task;
      task.set_task_id(BuildTaskId(size.spec.size, i));
      task.set_size(size.spec.size);
      task.set_example_index(static_cast<uint32_t>(i));
      task.set_label(size.plan.design.Label(static_cast<int>(i)));
      task.set_drape_key(drape.key);
      if (stored.contains(drape.key)) {
        task.set_phase(v1::TASK_DONE);
        task.set_cache_hit(true);
      } else {
        task.set_phase(v1::TASK_QUEUED);
        // In flight for another build (or earlier in this one): one execution serves both.
        task.set_cache_hit(executions_.contains(drape.key));
      }
      v1::Task& placed = run->tasks[task.task_id()] = std::move(task);
      if (placed.phase() == v1::TASK_QUEUED) to_run.push_back(&placed);
    }
  }
  build.set_tasks_total(static_cast<uint32_t>(run->tasks.size()));
  uint32_t hits = 0;
  for (const auto& [id, task] : run->tasks) hits += task.cache_hit();
  build.set_cache_hits(hits);
  ++next_build_number_;
  const int64_t vertex_count = plan->garment.template_mesh().vertex_count();
  for (v1::Task* task : to_run) JoinExecutionLocked(*run, *task, vertex_count);
  MaybeAssembleLocked(*run);

  storage::AssetWrite write;
  PutRunLocked(*run, write);
  for (const auto& [id, task] : run->tasks)
    write.PutTask(build.build_id(), id, proto::SerializeDeterministically(task));
  BuildRun& placed = *(builds_[build.build_id()] = std::move(run));
  TouchLocked(placed);
  RETURN_IF_ERROR(CommitLocked(write, /*sync=*/true));
  plans_.Put(placed.build.build_id(), plan);
  core::LogLine("build_submitted")
      .Add("build", placed.build.build_id())
      .Add("tenant", tenant)
      .Add("garment", placed.build.request().garment_id())
      .Add("tasks", placed.build.tasks_total())
      .Add("cache_hits", placed.build.cache_hits());
  return placed.build;
}

absl::StatusOr<BuildSnapshot> Coordinator::GetBuild(absl::string_view tenant,
                                                    absl::string_view build_id,
                                                    bool with_tasks) const {
  std::lock_guard lock(mutex_);
  const BuildRun* run = FindBuildLocked(tenant, build_id);
  if (run == nullptr) return absl::NotFoundError(absl::StrCat("build ", build_id, " not found"));
  BuildSnapshot snapshot{run->build, {}, run->revision};
  if (with_tasks) {
    for (const auto& [id, task] : run->tasks) snapshot.tasks.push_back(task);
  }
  return snapshot;
}

std::vector<v1::Build> Coordinator::ListBuilds(absl::string_view tenant) const {
  std::lock_guard lock(mutex_);
  std::vector<v1::Build> builds;
  for (const auto& [id, run] : builds_) {
    if (run->build.tenant() == tenant) builds.push_back(run->build);
  }
  return builds;
}

absl::StatusOr<BuildSnapshot> Coordinator::WaitForBuild(absl::string_view tenant,
                                                        absl::string_view build_id,
                                                        uint64_t after_revision,
                                                        absl::Time deadline) const {
  std::unique_lock lock(mutex_);
  while (true) {
    const BuildRun* run = FindBuildLocked(tenant, build_id);
    if (run == nullptr) return absl::NotFoundError(absl::StrCat("build ", build_id, " not found"));
    if (run->revision > after_revision || IsTerminal(run->build.phase()) || shutdown_ ||
        !broken_.ok() || absl::Now() >= deadline) {
      return BuildSnapshot{run->build, {}, run->revision};
    }
    builds_changed_.wait_until(lock, absl::ToChronoTime(deadline));
  }
}

void Coordinator::RemoveWaitersLocked(const BuildRun& run) {
  std::vector<std::string> emptied;
  for (auto& [key, execution] : executions_) {
    std::erase_if(execution.waiters, [&](const Waiter& waiter) {
      return waiter.build_id == run.build.build_id();
    });
    if (execution.waiters.empty()) emptied.push_back(key);
  }
  // A leased execution nobody waits for is dropped too: its worker's heartbeat and completion
  // are then refused.
  for (const std::string& key : emptied) executions_.erase(key);
}

void Coordinator::EndBuildLocked(BuildRun& run, v1::BuildPhase phase, const std::string& error,
                                 storage::AssetWrite& write) {
  run.build.set_phase(phase);
  run.build.set_error(error);
  run.build.set_finished_unix_ms(UnixMillis(Now()));
  for (auto& [id, task] : run.tasks) {
    if (!IsOpen(task.phase())) continue;
    task.set_phase(v1::TASK_CANCELLED);
    ClearLease(task);
    write.PutTask(run.build.build_id(), id, proto::SerializeDeterministically(task));
  }
  RemoveWaitersLocked(run);
  MaybeAssembleLocked(run);
  PutRunLocked(run, write);
  TouchLocked(run);
  core::LogLine(phase == v1::BUILD_FAILED ? "build_failed" : "build_cancelled")
      .Add("build", run.build.build_id())
      .Add("error", error);
}

absl::StatusOr<v1::Build> Coordinator::Cancel(absl::string_view tenant,
                                              absl::string_view build_id) {
  std::lock_guard lock(mutex_);
  RETURN_IF_ERROR(CheckUsableLocked());
  BuildRun* run = FindBuildLocked(tenant, build_id);
  if (run == nullptr) return absl::NotFoundError(absl::StrCat("build ", build_id, " not found"));
  if (IsTerminal(run->build.phase()) || run->build.phase() == v1::BUILD_ASSEMBLING) {
    return absl::FailedPreconditionError(
        absl::StrCat("build ", build_id, " is ", v1::BuildPhase_Name(run->build.phase()),
                     " and can no longer be cancelled"));
  }
  storage::AssetWrite write;
  EndBuildLocked(*run, v1::BUILD_CANCELLED, "cancelled", write);
  RETURN_IF_ERROR(CommitLocked(write, /*sync=*/true));
  return run->build;
}

int Coordinator::ReapExpiredLeases() {
  std::lock_guard lock(mutex_);
  if (!broken_.ok()) return 0;
  return ReapExpiredLeasesLocked();
}

int Coordinator::ReapExpiredLeasesLocked() {
  const absl::Time now = Now();
  std::vector<std::string> expired;
  for (const auto& [key, execution] : executions_) {
    if (execution.leased && execution.expiry <= now) expired.push_back(key);
  }
  for (const std::string& key : expired) {
    Execution& execution = executions_.at(key);
    core::LogLine("lease_expired")
        .Add("key", key)
        .Add("token", execution.token)
        .Add("worker", execution.worker);
    if (!FailAttemptLocked(execution, absl::StrCat("the lease of worker ", execution.worker,
                                                   " expired"))
             .ok()) {
      break;
    }
  }
  return static_cast<int>(expired.size());
}

absl::StatusOr<std::optional<LeasedTask>> Coordinator::Lease(absl::string_view worker,
                                                             absl::Time deadline) {
  std::unique_lock lock(mutex_);
  Execution* granted = nullptr;
  while (granted == nullptr) {
    RETURN_IF_ERROR(CheckUsableLocked());
    if (shutdown_) return std::nullopt;
    ReapExpiredLeasesLocked();
    while (!queue_.empty() && granted == nullptr) {
      auto it = executions_.find(queue_.front());
      queue_.pop_front();
      if (it != executions_.end() && !it->second.leased) granted = &it->second;
    }
    if (granted == nullptr &&
        queue_changed_.wait_until(lock, absl::ToChronoTime(deadline)) ==
            std::cv_status::timeout) {
      return std::nullopt;
    }
  }
  Execution& execution = *granted;
  execution.leased = true;
  execution.token = next_token_++;
  execution.expiry = Now() + options_.lease;
  execution.worker = std::string(worker);
  storage::AssetWrite write;
  UpdateWaitersLocked(
      execution.waiters,
      [&](const Waiter& waiter, v1::Task& task) {
        task.set_phase(v1::TASK_LEASED);
        task.set_worker(execution.worker);
        task.set_lease_token(execution.token);
        task.set_lease_expiry_unix_ms(UnixMillis(execution.expiry));
        task.set_leases(task.leases() + 1);
        core::LogLine("task_leased")
            .Add("build", waiter.build_id)
            .Add("task", task.task_id())
            .Add("key", execution.key)
            .Add("token", execution.token)
            .Add("attempt", execution.attempts + 1)
            .Add("worker", worker);
      },
      write);
  // Synced: a token must never be granted twice, even across a crash.
  RETURN_IF_ERROR(CommitLocked(write, /*sync=*/true));
  LeasedTask leased;
  leased.lease.set_key(execution.key);
  leased.lease.set_token(execution.token);
  leased.lease.set_expiry_unix_ms(UnixMillis(execution.expiry));
  leased.lease.set_attempt(execution.attempts + 1);
  leased.lease.set_duration_ms(static_cast<uint32_t>(absl::ToInt64Milliseconds(options_.lease)));
  // Any waiting build's task gives the spec: equal keys are equal content.
  const BuildRun& run = *builds_.at(execution.waiters.front().build_id);
  const v1::Task& task = run.tasks.at(execution.waiters.front().task_id);
  const std::string build_id = run.build.build_id();
  const std::string tenant = run.build.tenant();
  const v1::BuildRequest request = run.build.request();
  const std::string size = task.size();
  const uint32_t example = task.example_index();
  lock.unlock();
  ASSIGN_OR_RETURN(std::shared_ptr<const BuildPlan> plan, PlanOf(build_id, tenant, request));
  for (const BuildPlan::Size& planned : plan->sizes) {
    if (planned.spec.size != size || example >= planned.plan.tasks.size()) continue;
    const workers::DrapeTask& drape = planned.plan.tasks[example];
    if (drape.key != leased.lease.key()) break;
    leased.spec = workers::DrapeTaskToSpec(drape);
    return leased;
  }
  return absl::InternalError(absl::StrCat("build ", build_id, " plans task ", size, "/",
                                          example, " as another drape than ",
                                          leased.lease.key()));
}

absl::StatusOr<std::shared_ptr<const BuildPlan>> Coordinator::PlanOf(
    const std::string& build_id, const std::string& tenant, const v1::BuildRequest& request) {
  return plans_.Get(build_id, [&] { return PlanBuild(*store_, tenant, request); });
}

absl::StatusOr<Coordinator::Execution*> Coordinator::FindLeaseLocked(absl::string_view key,
                                                                     uint64_t token) {
  auto it = executions_.find(std::string(key));
  if (it == executions_.end()) {
    auto done = completed_tokens_.find(std::string(key));
    if (done != completed_tokens_.end()) {
      return absl::FailedPreconditionError(
          absl::StrCat("lease ", token, " of task ", key, " is stale: lease ", done->second,
                       " completed it"));
    }
    return absl::NotFoundError(absl::StrCat("task ", key, " is not in flight"));
  }
  Execution& execution = it->second;
  if (!execution.leased || execution.token != token) {
    return absl::FailedPreconditionError(absl::StrCat(
        "lease ", token, " of task ", key, " is stale: ",
        execution.leased ? absl::StrCat("lease ", execution.token, " holds it now")
                         : std::string("it is queued again")));
  }
  return &execution;
}

absl::StatusOr<absl::Time> Coordinator::Heartbeat(absl::string_view key, uint64_t token) {
  std::lock_guard lock(mutex_);
  RETURN_IF_ERROR(CheckUsableLocked());
  ASSIGN_OR_RETURN(Execution * execution, FindLeaseLocked(key, token));
  // Not written to the store: a restart gives every live lease a full period anyway.
  execution->expiry = Now() + options_.lease;
  return execution->expiry;
}

absl::Status Coordinator::Complete(absl::string_view key, uint64_t token,
                                   const v1::DrapeResult& result) {
  std::lock_guard lock(mutex_);
  RETURN_IF_ERROR(CheckUsableLocked());
  if (auto done = completed_tokens_.find(std::string(key));
      done != completed_tokens_.end() && done->second == token) {
    return absl::OkStatus();  // A repeated completion whose answer was lost.
  }
  ASSIGN_OR_RETURN(Execution * execution, FindLeaseLocked(key, token));
  const int64_t vertex_count = execution->vertex_count;
  std::string problem;
  if (result.key() != key) {
    problem = absl::StrCat("the result is for task ", result.key());
  } else if (result.positions_size() != 3 * vertex_count) {
    problem = absl::StrCat("the result has ", result.positions_size(), " coordinates; expected ",
                           3 * vertex_count);
  } else if (!std::all_of(result.positions().begin(), result.positions().end(),
                          [](float v) { return std::isfinite(v); })) {
    problem = "the result has non-finite positions";
  }
  if (!problem.empty()) {
    const std::string error = absl::StrCat("invalid result of task ", key, ": ", problem);
    RETURN_IF_ERROR(FailAttemptLocked(*execution, error));
    return absl::InvalidArgumentError(error);
  }

  storage::AssetWrite write;
  write.PutDrapeResult(key, proto::SerializeDeterministically(result));
  UpdateWaitersLocked(
      execution->waiters,
      [&](const Waiter& waiter, v1::Task& task) {
        task.set_phase(v1::TASK_DONE);
        ClearLease(task);
        core::LogLine("task_done")
            .Add("build", waiter.build_id)
            .Add("task", task.task_id())
            .Add("key", key)
            .Add("token", token);
      },
      write);
  completed_tokens_[std::string(key)] = token;
  executions_.erase(std::string(key));
  return CommitLocked(write, /*sync=*/true);
}

absl::Status Coordinator::Fail(absl::string_view key, uint64_t token, absl::string_view error,
                               bool returned) {
  std::lock_guard lock(mutex_);
  RETURN_IF_ERROR(CheckUsableLocked());
  ASSIGN_OR_RETURN(Execution * execution, FindLeaseLocked(key, token));
  core::LogLine(returned ? "lease_returned" : "attempt_failed")
      .Add("key", key)
      .Add("token", token)
      .Add("worker", execution->worker)
      .Add("error", error);
  if (!returned) return FailAttemptLocked(*execution, std::string(error));
  execution->leased = false;
  queue_.push_front(execution->key);
  queue_changed_.notify_one();
  storage::AssetWrite write;
  UpdateWaitersLocked(
      execution->waiters,
      [](const Waiter&, v1::Task& task) {
        task.set_phase(v1::TASK_QUEUED);
        ClearLease(task);
      },
      write);
  return CommitLocked(write, /*sync=*/true);
}

absl::Status Coordinator::FailAttemptLocked(Execution& execution, const std::string& error) {
  const std::string key = execution.key;
  const uint32_t attempts = ++execution.attempts;
  execution.leased = false;
  const bool final = attempts >= options_.max_attempts;
  const std::vector<Waiter> waiters = execution.waiters;
  storage::AssetWrite write;
  const std::vector<BuildRun*> runs = UpdateWaitersLocked(
      waiters,
      [&](const Waiter&, v1::Task& task) {
        task.set_phase(final ? v1::TASK_FAILED : v1::TASK_QUEUED);
        task.set_attempts(attempts);
        task.set_error(error);
        ClearLease(task);
      },
      write);
  if (final) {
    executions_.erase(key);
    for (BuildRun* run : runs) {
      if (IsTerminal(run->build.phase())) continue;
      std::string task_id;
      for (const Waiter& waiter : waiters) {
        if (waiter.build_id == run->build.build_id()) task_id = waiter.task_id;
      }
      EndBuildLocked(*run, v1::BUILD_FAILED,
                     absl::StrCat("task ", task_id, " (drape ", key, ") failed ", attempts,
                                  " times; last error: ", error),
                     write);
    }
  } else {
    queue_.push_back(key);
    queue_changed_.notify_one();
  }
  return CommitLocked(write, /*sync=*/true);
}

void Coordinator::RunAssembler() {
  std::unique_lock lock(mutex_);
  while (true) {
    builds_changed_.wait(lock, [&] { return shutdown_ || !assembly_queue_.empty(); });
    if (shutdown_) return;
    const std::string build_id = assembly_queue_.front();
    assembly_queue_.pop_front();
    lock.unlock();
    Assemble(build_id);
    lock.lock();
    builds_changed_.notify_all();
  }
}

void Coordinator::Assemble(const std::string& build_id) {
  std::string tenant;
  v1::BuildRequest request;
  {
    std::lock_guard lock(mutex_);
    tenant = builds_.at(build_id)->build.tenant();
    request = builds_.at(build_id)->build.request();
  }
  const absl::Time start = absl::Now();
  std::vector<v1::PublishedClothingBasis> published;
  absl::Status status = [&]() -> absl::Status {
    ASSIGN_OR_RETURN(std::shared_ptr<const BuildPlan> plan, PlanOf(build_id, tenant, request));
    ASSIGN_OR_RETURN(std::vector<v1::ClothingBasis> bases,
                     AssembleBuild(*store_, *plan, options_.assembly_threads));
    for (const v1::ClothingBasis& basis : bases) {
      const storage::ClothingBasisKey key{plan->tenant, basis.garment_id(), basis.size(),
                                          basis.avatar_basis_id(), basis.method()};
      ASSIGN_OR_RETURN(
          uint64_t version,
          store_->PublishClothingBasis(key, basis.id(), proto::SerializeDeterministically(basis)));
      v1::PublishedClothingBasis& entry = published.emplace_back();
      entry.set_size(basis.size());
      entry.set_method(basis.method());
      entry.set_clothing_basis_id(basis.id());
      entry.set_version(version);
    }
    return absl::OkStatus();
  }();
  std::lock_guard lock(mutex_);
  BuildRun& run = *builds_.at(build_id);
  storage::AssetWrite write;
  if (status.ok()) {
    run.build.set_phase(v1::BUILD_SUCCEEDED);
    run.build.set_finished_unix_ms(UnixMillis(Now()));
    run.build.mutable_published()->Assign(published.begin(), published.end());
    PutRunLocked(run, write);
    TouchLocked(run);
    core::LogLine("build_published")
        .Add("build", build_id)
        .Add("bases", published.size())
        .Add("assembly_seconds", absl::ToDoubleSeconds(absl::Now() - start));
  } else {
    EndBuildLocked(run, v1::BUILD_FAILED, absl::StrCat("assembly failed: ", status.ToString()),
                   write);
  }
  CommitLocked(write, /*sync=*/true).IgnoreError();
}

absl::Status Coordinator::Recover() {
  ASSIGN_OR_RETURN(std::vector<storage::JobRecord> records, store_->ListBuilds());
  storage::AssetWrite write;
  std::lock_guard lock(mutex_);
  for (const storage::JobRecord& record : records) {
    auto run = std::make_unique<BuildRun>();
    if (!run->build.ParseFromString(record.bytes)) {
      return absl::DataLossError(absl::StrCat("stored build ", record.id, " does not parse"));
    }
    uint64_t number = 0;
    if (absl::string_view id = record.id; absl::ConsumePrefix(&id, kBuildIdPrefix) &&
                                          absl::SimpleAtoi(id, &number)) {
      next_build_number_ = std::max(next_build_number_, number + 1);
    }
    ASSIGN_OR_RETURN(std::vector<storage::JobRecord> tasks, store_->ListTasks(record.id));
    for (const storage::JobRecord& task_record : tasks) {
      v1::Task task;
      if (!task.ParseFromString(task_record.bytes)) {
        return absl::DataLossError(absl::StrCat("stored task ", task_record.id, " of build ",
                                                record.id, " does not parse"));
      }
      next_token_ = std::max(next_token_, task.lease_token() + 1);
      run->tasks[task.task_id()] = std::move(task);
    }
    BuildRun& placed = *(builds_[record.id] = std::move(run));
    if (!IsTerminal(placed.build.phase())) RETURN_IF_ERROR(RecoverBuild(placed, write));
    TouchLocked(placed);
  }
  return CommitLocked(write, /*sync=*/true);
}

absl::Status Coordinator::RecoverBuild(BuildRun& run, storage::AssetWrite& write) {
  absl::StatusOr<std::unique_ptr<const BuildPlan>> plan =
      PlanBuild(*store_, run.build.tenant(), run.build.request());
  if (!plan.ok()) {
    EndBuildLocked(run, v1::BUILD_FAILED,
                   absl::StrCat("re-planning after a restart failed: ", plan.status().ToString()),
                   write);
    return absl::OkStatus();
  }
  std::shared_ptr<const BuildPlan> planned = *std::move(plan);
  std::map<std::string, const workers::DrapeTask*> drapes;
  for (const BuildPlan::Size& size : planned->sizes) {
    for (size_t i = 0; i < size.plan.tasks.size(); ++i) {
      drapes[BuildTaskId(size.spec.size, i)] = &size.plan.tasks[i];
    }
  }
  int resumed = 0;
  for (auto& [id, task] : run.tasks) {
    if (!IsOpen(task.phase())) continue;
    auto drape = drapes.find(id);
    if (drape == drapes.end() || drape->second->key != task.drape_key()) {
      EndBuildLocked(run, v1::BUILD_FAILED,
                     absl::StrCat("task ", id, " re-plans to another drape after a restart"),
                     write);
      return absl::OkStatus();
    }
    ASSIGN_OR_RETURN(bool stored, HasDrapeResult(task.drape_key()));
    if (stored) {
      task.set_phase(v1::TASK_DONE);
      ClearLease(task);
      write.PutTask(run.build.build_id(), id, proto::SerializeDeterministically(task));
      continue;
    }
    ++resumed;
    JoinExecutionLocked(run, task, planned->garment.template_mesh().vertex_count());
    Execution& execution = executions_.at(task.drape_key());
    if (task.phase() == v1::TASK_LEASED && !execution.leased) {
      // The worker may still be draping: it gets a full lease period to report to us.
      execution.leased = true;
      execution.token = task.lease_token();
      execution.worker = task.worker();
      execution.expiry = Now() + options_.lease;
    }
  }
  MaybeAssembleLocked(run);
  PutRunLocked(run, write);
  plans_.Put(run.build.build_id(), planned);
  core::LogLine("build_resumed")
      .Add("build", run.build.build_id())
      .Add("phase", v1::BuildPhase_Name(run.build.phase()))
      .Add("tasks_open", resumed)
      .Add("tasks_done", run.build.tasks_done());
  return absl::OkStatus();
}

}  // namespace fitbase::build
