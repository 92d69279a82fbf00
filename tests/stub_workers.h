#ifndef FITBASE_TESTS_STUB_WORKERS_H_
#define FITBASE_TESTS_STUB_WORKERS_H_

// Workers with a stub drape, for the coordinator under many leases at once (the correctness
// test and fitbase_build_bench): each thread leases over a real WorkerQueue channel, heartbeats,
// tries a completion under a token that is not its lease's, and completes with the garment's
// template positions, recording whatever breaks the lease rules.
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "absl/time/time.h"
#include "fitbase/v1/worker_queue.grpc.pb.h"
#include "grpcpp/grpcpp.h"
#include "services/rpc/call_auth.h"

namespace fitbase {

class StubWorkers {
 public:
  // What the workers saw, read once they stopped.
  struct Report {
    int64_t completed = 0;
    int64_t concurrent_double_leases = 0;  // A key leased while another worker held it.
    int64_t foreign_tokens_accepted = 0;   // Completions under a token not the lease's.
    int64_t failed_calls = 0;
    std::string first_failure;
    std::map<std::string, int> completions;  // Accepted completions per key.
  };

  // `count` threads, each with a channel of its own, as separate worker processes would.
  StubWorkers(const std::string& address, const std::string& key, int count,
              absl::Duration lease_wait = absl::Seconds(1))
      : key_(key), lease_wait_(lease_wait) {
    for (int i = 0; i < count; ++i) {
      grpc::ChannelArguments arguments;
      arguments.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
      arguments.SetMaxReceiveMessageSize(64 << 20);
      stubs_.push_back(v1::WorkerQueue::NewStub(
          grpc::CreateCustomChannel(address, grpc::InsecureChannelCredentials(), arguments)));
    }
    for (int i = 0; i < count; ++i) threads_.emplace_back([this, i] { Run(i); });
  }
  ~StubWorkers() { Stop(); }

  int64_t completed() const { return completed_.load(); }

  // Ends every thread after its call in flight; safe to call twice.
  Report Stop() {
    stopping_ = true;
    for (std::thread& thread : threads_) {
      if (thread.joinable()) thread.join();
    }
    std::lock_guard lock(mutex_);
    report_.completed = completed_.load();
    return report_;
  }

 private:
  std::unique_ptr<grpc::ClientContext> Context(absl::Duration timeout) const {
    auto context = std::make_unique<grpc::ClientContext>();
    context->set_deadline(absl::ToChronoTime(absl::Now() + timeout));
    // A worker rides out a coordinator it cannot reach for a moment. On a loaded machine one of
    // 16 channels connecting at once can fail its connection ("failed to connect to all
    // addresses"); without this, each call on it fails at once until gRPC reconnects (12,766
    // failed calls in 3.9 s, two busy loops beside the test), which is no fault of the
    // coordinator's.
    context->set_wait_for_ready(true);
    rpc::AddApiKey(*context, key_);
    return context;
  }

  void Failed(const std::string& what) {
    std::lock_guard lock(mutex_);
    if (report_.failed_calls++ == 0) report_.first_failure = what;
  }

  void Run(int index) {
    v1::WorkerQueue::Stub& stub = *stubs_[index];
    const std::string name = absl::StrCat("stub-", index);
    while (!stopping_) {
      v1::LeaseTaskRequest lease_request;
      lease_request.set_worker(name);
      lease_request.set_wait_ms(static_cast<uint32_t>(absl::ToInt64Milliseconds(lease_wait_)));
      v1::LeaseTaskResponse leased;
      const grpc::Status status =
          stub.LeaseTask(Context(lease_wait_ + absl::Seconds(30)).get(), lease_request, &leased);
      if (!status.ok()) {
        Failed(absl::StrCat("LeaseTask: ", status.error_message()));
        continue;
      }
      if (!leased.has_lease()) continue;
      const v1::Lease& lease = leased.lease();
      {
        std::lock_guard lock(mutex_);
        if (!held_.insert(lease.key()).second) ++report_.concurrent_double_leases;
      }
      v1::HeartbeatRequest beat;
      beat.set_key(lease.key());
      beat.set_token(lease.token());
      v1::HeartbeatResponse beaten;
      if (grpc::Status s = stub.Heartbeat(Context(absl::Seconds(30)).get(), beat, &beaten);
          !s.ok()) {
        Failed(absl::StrCat("Heartbeat: ", s.error_message()));
      }
      v1::CompleteTaskRequest complete;
      complete.set_key(lease.key());
      // The fencing check: no token but the lease's may complete the task.
      complete.set_token(lease.token() + (uint64_t{1} << 40));
      complete.mutable_result()->set_key(lease.key());
      *complete.mutable_result()->mutable_positions() =
          leased.spec().garment().template_mesh().positions();
      v1::CompleteTaskResponse completed;
      const grpc::Status foreign =
          stub.CompleteTask(Context(absl::Seconds(30)).get(), complete, &completed);
      if (foreign.error_code() != grpc::StatusCode::FAILED_PRECONDITION) {
        std::lock_guard lock(mutex_);
        ++report_.foreign_tokens_accepted;
      }
      complete.set_token(lease.token());
      const grpc::Status done =
          stub.CompleteTask(Context(absl::Seconds(30)).get(), complete, &completed);
      std::lock_guard lock(mutex_);
      held_.erase(lease.key());
      if (done.ok()) {
        ++report_.completions[lease.key()];
        ++completed_;
      } else if (report_.failed_calls++ == 0) {
        report_.first_failure = absl::StrCat("CompleteTask: ", done.error_message());
      }
    }
  }

  const std::string key_;
  const absl::Duration lease_wait_;
  std::vector<std::unique_ptr<v1::WorkerQueue::Stub>> stubs_;
  std::atomic<bool> stopping_{false};
  std::atomic<int64_t> completed_{0};
  std::mutex mutex_;
  std::set<std::string> held_;  // Keys leased and not yet completed.
  Report report_;
  std::vector<std::thread> threads_;  // Last: started once the members above exist.
};

}  // namespace fitbase

#endif  // FITBASE_TESTS_STUB_WORKERS_H_
