#ifndef FITBASE_WORKERS_DRAPE_WORKER_H_
#define FITBASE_WORKERS_DRAPE_WORKER_H_

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "absl/status/status.h"
#include "absl/time/time.h"
#include "fitbase/v1/worker_queue.grpc.pb.h"
#include "grpcpp/grpcpp.h"

namespace fitbase::workers {

struct DrapeWorkerOptions {
  std::string coordinator;  // host:port of the coordinator's WorkerQueue.
  std::shared_ptr<grpc::ChannelCredentials> credentials;  // Null: insecure.
  // With TLS: the name the coordinator's certificate must carry, when it differs from the
  // address's host (e.g. "fitbase-coordinator" reached as 127.0.0.1).
  std::string tls_target_name;
  std::string api_key;      // Sent as x-api-key; a key of the worker role.
  int slots = 1;            // Drapes run side by side, each on one thread.
  std::string name;         // Names this worker in leases and logs; slots add "/<slot>".
  absl::Duration lease_wait = absl::Seconds(20);  // Long-poll of LeaseTask.
  absl::Duration rpc_timeout = absl::Seconds(30); // Deadline of every other call.
  // Reconnection after failed calls: doubling from the first to the last delay.
  absl::Duration backoff_first = absl::Milliseconds(100);
  absl::Duration backoff_last = absl::Seconds(5);
  // Attempts to deliver one completion before giving the task up to the lease expiry.
  int completion_attempts = 30;
  int max_message_bytes = 64 << 20;
};

// A worker of the distributed build: each slot leases a drape task from the coordinator, drapes
// it (RunDrapeTask, the code the local build runs), and completes it; a heartbeat thread keeps
// the leases of running drapes alive. Calls that fail for want of a coordinator are retried
// with backoff, so a worker survives coordinator restarts; a refused completion (stale lease)
// is dropped, since the task's current lease holder delivers it.
class DrapeWorker {
 public:
  explicit DrapeWorker(DrapeWorkerOptions options);
  ~DrapeWorker();
  DrapeWorker(const DrapeWorker&) = delete;
  DrapeWorker& operator=(const DrapeWorker&) = delete;

  // Runs the slots until Drain() and their drapes finish.
  void Run();
  // Takes no new task; running drapes finish and complete. Safe from any thread.
  void Drain();
  // Gives every running task back to the coordinator unrun (FailTask with `returned`), so
  // another worker takes it without an attempt counted. For a shutdown that cannot wait.
  void ReturnLeases();

  int64_t completed() const { return completed_.load(); }

 private:
  struct ActiveLease {
    std::string key;
    uint64_t token = 0;
    absl::Duration duration;
    absl::Time next_heartbeat;
  };

  void RunSlot(int slot);
  void RunHeartbeats();
  // Runs one leased task to its completion or failure report.
  void Execute(const std::string& worker, const v1::LeaseTaskResponse& leased);
  void Deliver(const v1::CompleteTaskRequest& request);
  void ReportFailure(const std::string& key, uint64_t token, const absl::Status& error);
  std::unique_ptr<grpc::ClientContext> NewContext(absl::Duration timeout) const;
  // Waits `delay` or until Drain(); false when draining.
  bool Backoff(absl::Duration delay);

  const DrapeWorkerOptions options_;
  std::unique_ptr<v1::WorkerQueue::Stub> stub_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool draining_ = false;
  int running_slots_ = 0;
  std::map<int, ActiveLease> active_;  // By slot.
  std::map<int, grpc::ClientContext*> polls_;  // Each slot's LeaseTask in flight, to cancel.
  std::atomic<int64_t> completed_{0};
  std::atomic<int64_t> failed_{0};
};

}  // namespace fitbase::workers

#endif  // FITBASE_WORKERS_DRAPE_WORKER_H_
