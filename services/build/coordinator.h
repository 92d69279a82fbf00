#ifndef FITBASE_SERVICES_BUILD_COORDINATOR_H_
#define FITBASE_SERVICES_BUILD_COORDINATOR_H_

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/container/node_hash_map.h"
#include "absl/functional/function_ref.h"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "absl/time/time.h"
#include "fitbase/v1/build.pb.h"
#include "fitbase/v1/clothing_basis.pb.h"
#include "fitbase/v1/worker_queue.pb.h"
#include "services/build/build_plan.h"
#include "services/build/plan_cache.h"
#include "services/rpc/clock.h"
#include "storage/asset_store.h"

namespace fitbase::build {

struct CoordinatorOptions {
  const rpc::Clock* clock = nullptr;  // Null: the real clock.
  // How long a lease lasts without a heartbeat.
  absl::Duration lease = absl::Seconds(30);
  // Failed or expired attempts after which a task, and every build waiting for it, fails.
  uint32_t max_attempts = 3;
  // Build plans kept in memory (PlanCache): tens of MB each, while a queued task costs ~3 KB.
  // Leases take tasks in submission order, so a few plans serve them all.
  size_t cached_plans = 4;
  // Threads of one kernel model's search when a build is assembled (KernelBuildOptions::threads:
  // the kernel shapes side by side). The bases are the same bytes for any count.
  int assembly_threads = 2;
};

// A build as seen at one moment, and the revision that moment has (for WaitForBuild).
struct BuildSnapshot {
  v1::Build build;
  std::vector<v1::Task> tasks;  // Only when asked for.
  uint64_t revision = 0;
};

// A leased task: the lease and what the worker runs.
struct LeasedTask {
  v1::Lease lease;
  v1::DrapeTaskSpec spec;
};

// The build coordinator, after the Remote Execution API's execution service:
//
// - A build is split into one task per (size, example avatar). Each task is content-addressed
//   by its drape key; a key whose result is stored completes at once (a cache hit), and tasks
//   of the same key in flight, in any builds, share one execution (also a cache hit).
// - Executions are leased to workers for `lease`, extended by heartbeats, with a fencing
//   token unique across restarts. Heartbeats, completions and failures with another token
//   than the current lease's are FAILED_PRECONDITION. An expired lease or a failure counts an
//   attempt; after max_attempts the task and its builds fail with the last error. Completion is
//   idempotent: the holder of the completing lease may repeat it.
// - A completion stores the drape result and every waiting task's new state in one synced
//   write. When a build's last task is done it is assembled (AssembleBuild, the local build's
//   code) on a background thread and each clothing basis is published; publication is
//   idempotent, so an assembly repeated after a crash publishes nothing new.
// - All state lives in the store: Open() resumes every unfinished build, keeping its done tasks
//   and its live leases (given one lease period from the restart to report back).
// - Memory grows with the tasks (~3 KB each), not with their plans: the plan a
//   lease or an assembly needs is planned again when it is not among the cached ones.
//
// Every method is thread-safe. Callers are authenticated: `tenant` is the caller's, and a build
// of another tenant is NOT_FOUND.
class Coordinator {
 public:
  static absl::StatusOr<std::unique_ptr<Coordinator>> Open(storage::AssetStore* store,
                                                           const CoordinatorOptions& options);
  ~Coordinator();
  Coordinator(const Coordinator&) = delete;
  Coordinator& operator=(const Coordinator&) = delete;

  absl::StatusOr<v1::Build> Submit(absl::string_view tenant, const v1::BuildRequest& request);
  absl::StatusOr<BuildSnapshot> GetBuild(absl::string_view tenant, absl::string_view build_id,
                                         bool with_tasks) const;
  // The tenant's builds, oldest first.
  std::vector<v1::Build> ListBuilds(absl::string_view tenant) const;
  // FAILED_PRECONDITION for a build that already ended.
  absl::StatusOr<v1::Build> Cancel(absl::string_view tenant, absl::string_view build_id);
  // Waits until the build's revision passes `after_revision`, it has ended, `deadline`
  // (real time) passes or Shutdown(); returns its state then.
  absl::StatusOr<BuildSnapshot> WaitForBuild(absl::string_view tenant, absl::string_view build_id,
                                             uint64_t after_revision, absl::Time deadline) const;

  // The worker queue. Lease waits until a task is queued, `deadline` (real time) or
  // Shutdown(); nullopt when none came.
  absl::StatusOr<std::optional<LeasedTask>> Lease(absl::string_view worker, absl::Time deadline);
  // The lease's new expiry.
  absl::StatusOr<absl::Time> Heartbeat(absl::string_view key, uint64_t token);
  absl::Status Complete(absl::string_view key, uint64_t token, const v1::DrapeResult& result);
  absl::Status Fail(absl::string_view key, uint64_t token, absl::string_view error,
                    bool returned);
  // Counts an attempt for every lease expired by now and requeues or fails its task; returns
  // how many. Lease() calls it; a server also calls it periodically.
  int ReapExpiredLeases();

  // Wakes every waiting Lease and WaitForBuild, and stops the assembler.
  void Shutdown();

 private:
  struct BuildRun {
    v1::Build build;
    std::map<std::string, v1::Task> tasks;  // By task id.
    uint64_t revision = 0;
  };
  struct Waiter {
    std::string build_id;
    std::string task_id;
  };
  struct Execution {
    std::string key;
    int64_t vertex_count = 0;  // Of the garment: what a result must have.
    uint32_t attempts = 0;
    bool leased = false;
    uint64_t token = 0;
    absl::Time expiry;
    std::string worker;
    std::vector<Waiter> waiters;
  };

  Coordinator(storage::AssetStore* store, const CoordinatorOptions& options);
  absl::Status Recover();
  // Re-plans an unfinished build and requeues its tasks that are not done.
  absl::Status RecoverBuild(BuildRun& run, storage::AssetWrite& write);
  // OK, or the store failure that stopped this coordinator (see broken_).
  absl::Status CheckUsableLocked() const;
  // Commits a state change already made in memory; on failure the coordinator stops serving.
  absl::Status CommitLocked(const storage::AssetWrite& write, bool sync);
  absl::StatusOr<bool> HasDrapeResult(absl::string_view key) const;
  int ReapExpiredLeasesLocked();

  absl::Time Now() const { return clock_->Now(); }
  // The execution holding the lease (`key`, `token`), or FAILED_PRECONDITION / NOT_FOUND.
  absl::StatusOr<Execution*> FindLeaseLocked(absl::string_view key, uint64_t token);
  BuildRun* FindBuildLocked(absl::string_view tenant, absl::string_view build_id) const;
  // Adds the task to the execution of its key, creating and queueing one when none is in
  // flight; true when it joined one.
  bool JoinExecutionLocked(BuildRun& run, const v1::Task& task, int64_t vertex_count);
  // The build's plan, from the cache or planned again. Call without mutex_.
  absl::StatusOr<std::shared_ptr<const BuildPlan>> PlanOf(const std::string& build_id,
                                                         const std::string& tenant,
                                                         const v1::BuildRequest& request);
  // Counts a failed attempt of the execution: requeues it, or fails it and its builds.
  absl::Status FailAttemptLocked(Execution& execution, const std::string& error);
  // Ends a build (failed or cancelled) and drops its unfinished tasks from their executions.
  void EndBuildLocked(BuildRun& run, v1::BuildPhase phase, const std::string& error,
                      storage::AssetWrite& write);
  void RemoveWaitersLocked(const BuildRun& run);
  // Marks a build whose every task is done ASSEMBLING and queues it for the assembler.
  void MaybeAssembleLocked(BuildRun& run);
  void TouchLocked(BuildRun& run);
  // Applies `update` to every waiting task, records it and its build in `write`, and returns
  // the builds (once per waiter).
  std::vector<BuildRun*> UpdateWaitersLocked(
      const std::vector<Waiter>& waiters, absl::FunctionRef<void(const Waiter&, v1::Task&)> update,
      storage::AssetWrite& write);
  void PutRunLocked(const BuildRun& run, storage::AssetWrite& write) const;
  void RunAssembler();
  void Assemble(const std::string& build_id);

  storage::AssetStore* const store_;
  const CoordinatorOptions options_;
  const rpc::RealClock real_clock_;
  const rpc::Clock* const clock_;

  mutable std::mutex mutex_;
  mutable std::condition_variable queue_changed_;
  mutable std::condition_variable builds_changed_;
  bool shutdown_ = false;
  // Set when a write of a state change failed: memory is then ahead of the store, so every
  // call is refused until a restart recovers from the store.
  absl::Status broken_;
  std::map<std::string, std::unique_ptr<BuildRun>> builds_;
  uint64_t next_build_number_ = 1;
  // Node map: Execution pointers stay valid while others are added and erased.
  absl::node_hash_map<std::string, Execution> executions_;
  std::deque<std::string> queue_;  // Keys of queued executions, oldest first.
  // The token that completed each key, so its holder may repeat the completion.
  absl::flat_hash_map<std::string, uint64_t> completed_tokens_;
  uint64_t next_token_ = 1;
  uint64_t revision_ = 0;
  std::deque<std::string> assembly_queue_;
  PlanCache plans_;
  std::thread assembler_;
};

}  // namespace fitbase::build

#endif  // FITBASE_SERVICES_BUILD_COORDINATOR_H_
