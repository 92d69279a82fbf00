#include "workers/drape_worker.h"

#include <algorithm>
#include <chrono>
#include <thread>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "core/log_line.h"
#include "workers/drape_task.h"
#include "workers/drape_task_spec.h"

namespace fitbase::workers {
namespace {

// Codes that say the coordinator could not be reached or was busy, not that it refused.
bool IsRetryable(grpc::StatusCode code) {
  return code == grpc::StatusCode::UNAVAILABLE || code == grpc::StatusCode::DEADLINE_EXCEEDED ||
         code == grpc::StatusCode::RESOURCE_EXHAUSTED || code == grpc::StatusCode::ABORTED;
}

std::chrono::system_clock::time_point Deadline(absl::Duration timeout) {
  return absl::ToChronoTime(absl::Now() + timeout);
}

}  // namespace

DrapeWorker::DrapeWorker(DrapeWorkerOptions options) : options_(std::move(options)) {
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(options_.max_message_bytes);
  arguments.SetMaxSendMessageSize(options_.max_message_bytes);
  // Reconnect quickly after a coordinator restart; the default backoff grows to two minutes.
  if (!options_.tls_target_name.empty()) {
    arguments.SetSslTargetNameOverride(options_.tls_target_name);
  }
  arguments.SetInt(GRPC_ARG_MAX_RECONNECT_BACKOFF_MS,
                   static_cast<int>(absl::ToInt64Milliseconds(options_.backoff_last)));
  stub_ = v1::WorkerQueue::NewStub(grpc::CreateCustomChannel(
      options_.coordinator,
      options_.credentials ? options_.credentials : grpc::InsecureChannelCredentials(),
      arguments));
}

DrapeWorker::~DrapeWorker() = default;

std::unique_ptr<grpc::ClientContext> DrapeWorker::NewContext(absl::Duration timeout) const {
  auto context = std::make_unique<grpc::ClientContext>();
  context->set_deadline(Deadline(timeout));
  if (!options_.api_key.empty()) context->AddMetadata("x-api-key", options_.api_key);
  return context;
}

bool DrapeWorker::Backoff(absl::Duration delay) {
  std::unique_lock lock(mutex_);
  wake_.wait_for(lock, absl::ToChronoNanoseconds(delay), [&] { return draining_; });
  return !draining_;
}

void DrapeWorker::Run() {
  {
    std::lock_guard lock(mutex_);
    running_slots_ = options_.slots;
  }
  std::thread heartbeats([this] { RunHeartbeats(); });
  std::vector<std::thread> slots;
  for (int slot = 0; slot < options_.slots; ++slot) {
    slots.emplace_back([this, slot] {
      RunSlot(slot);
      std::lock_guard lock(mutex_);
      --running_slots_;
      wake_.notify_all();
    });
  }
  for (std::thread& slot : slots) slot.join();
  heartbeats.join();
  core::LogLine("worker_stopped")
      .Add("worker", options_.name)
      .Add("completed", completed_.load())
      .Add("failed", failed_.load());
}

void DrapeWorker::Drain() {
  std::lock_guard lock(mutex_);
  if (draining_) return;
  draining_ = true;
  for (auto& [slot, context] : polls_) context->TryCancel();
  wake_.notify_all();
  core::LogLine("worker_draining").Add("worker", options_.name).Add("running", active_.size());
}

void DrapeWorker::ReturnLeases() {
  std::map<int, ActiveLease> active;
  {
    std::lock_guard lock(mutex_);
    active.swap(active_);
  }
  for (const auto& [slot, lease] : active) {
    v1::FailTaskRequest request;
    request.set_key(lease.key);
    request.set_token(lease.token);
    request.set_returned(true);
    request.set_error("worker shutting down");
    v1::FailTaskResponse response;
    const grpc::Status status =
        stub_->FailTask(NewContext(options_.rpc_timeout).get(), request, &response);
    core::LogLine("lease_returned")
        .Add("key", lease.key)
        .Add("token", lease.token)
        .Add("code", static_cast<int>(status.error_code()));
  }
}

void DrapeWorker::RunSlot(int slot) {
  const std::string worker = absl::StrCat(options_.name, "/", slot);
  absl::Duration backoff = options_.backoff_first;
  while (true) {
    v1::LeaseTaskRequest request;
    request.set_worker(worker);
    request.set_wait_ms(static_cast<uint32_t>(absl::ToInt64Milliseconds(options_.lease_wait)));
    // The deadline leaves the server time to answer an empty long-poll.
    std::unique_ptr<grpc::ClientContext> context =
        NewContext(options_.lease_wait + absl::Seconds(5));
    {
      std::lock_guard lock(mutex_);
      if (draining_) return;
      polls_[slot] = context.get();
    }
    v1::LeaseTaskResponse response;
    const grpc::Status status = stub_->LeaseTask(context.get(), request, &response);
    {
      std::lock_guard lock(mutex_);
      polls_.erase(slot);
      if (draining_ && !response.has_lease()) return;
    }
    if (!status.ok()) {
      if (!IsRetryable(status.error_code()) && status.error_code() != grpc::StatusCode::CANCELLED) {
        core::LogLine("lease_refused")
            .Add("worker", worker)
            .Add("code", static_cast<int>(status.error_code()))
            .Add("error", status.error_message());
      }
      if (!Backoff(backoff)) return;
      backoff = std::min(2 * backoff, options_.backoff_last);
      continue;
    }
    backoff = options_.backoff_first;
    if (response.has_lease()) {
      std::lock_guard lock(mutex_);
      active_[slot] = ActiveLease{
          response.lease().key(), response.lease().token(),
          absl::Milliseconds(response.lease().duration_ms()),
          absl::Now() + absl::Milliseconds(response.lease().duration_ms()) / 3};
      wake_.notify_all();
    } else {
      continue;
    }
    Execute(worker, response);
    std::lock_guard lock(mutex_);
    active_.erase(slot);
  }
}

void DrapeWorker::Execute(const std::string& worker, const v1::LeaseTaskResponse& leased) {
  const v1::Lease& lease = leased.lease();
  core::LogLine("task_started")
      .Add("worker", worker)
      .Add("key", lease.key())
      .Add("token", lease.token())
      .Add("attempt", lease.attempt());
  const absl::Time start = absl::Now();
  absl::StatusOr<DrapeTask> task = DrapeTaskFromSpec(leased.spec());
  if (task.ok() && task->key != lease.key()) {
    task = absl::InvalidArgumentError(
        absl::StrCat("lease for ", lease.key(), " carries task ", task->key));
  }
  absl::StatusOr<v1::DrapeResult> result =
      task.ok() ? RunDrapeTask(*task) : absl::StatusOr<v1::DrapeResult>(task.status());
  {
    std::lock_guard lock(mutex_);
    // ReturnLeases gave the task back while it ran: another worker owns it now.
    const bool still_ours = std::any_of(active_.begin(), active_.end(), [&](const auto& entry) {
      return entry.second.token == lease.token();
    });
    if (!still_ours) return;
  }
  if (!result.ok()) {
    ReportFailure(lease.key(), lease.token(), result.status());
    return;
  }
  core::LogLine("task_draped")
      .Add("worker", worker)
      .Add("key", lease.key())
      .Add("seconds", absl::ToDoubleSeconds(absl::Now() - start));
  v1::CompleteTaskRequest request;
  request.set_key(lease.key());
  request.set_token(lease.token());
  *request.mutable_result() = *std::move(result);
  Deliver(request);
}

void DrapeWorker::Deliver(const v1::CompleteTaskRequest& request) {
  absl::Duration backoff = options_.backoff_first;
  for (int attempt = 1; attempt <= options_.completion_attempts; ++attempt) {
    v1::CompleteTaskResponse response;
    const grpc::Status status =
        stub_->CompleteTask(NewContext(options_.rpc_timeout).get(), request, &response);
    if (status.ok()) {
      ++completed_;
      core::LogLine("task_completed").Add("key", request.key()).Add("token", request.token());
      return;
    }
    if (!IsRetryable(status.error_code())) {
      core::LogLine("completion_refused")
          .Add("key", request.key())
          .Add("token", request.token())
          .Add("code", static_cast<int>(status.error_code()))
          .Add("error", status.error_message());
      return;
    }
    // Completions are retried through a drain too: the result is the work done.
    std::this_thread::sleep_for(absl::ToChronoNanoseconds(backoff));
    backoff = std::min(2 * backoff, options_.backoff_last);
  }
  core::LogLine("completion_undelivered").Add("key", request.key()).Add("token", request.token());
}

void DrapeWorker::ReportFailure(const std::string& key, uint64_t token,
                                const absl::Status& error) {
  ++failed_;
  core::LogLine("task_failed").Add("key", key).Add("token", token).Add("error", error.ToString());
  v1::FailTaskRequest request;
  request.set_key(key);
  request.set_token(token);
  request.set_error(error.ToString());
  v1::FailTaskResponse response;
  const grpc::Status status =
      stub_->FailTask(NewContext(options_.rpc_timeout).get(), request, &response);
  if (!status.ok()) {
    // The lease expires and the coordinator counts the attempt then.
    core::LogLine("failure_undelivered").Add("key", key).Add("error", status.error_message());
  }
}

void DrapeWorker::RunHeartbeats() {
  std::unique_lock lock(mutex_);
  while (running_slots_ > 0) {
    absl::Time next = absl::InfiniteFuture();
    for (const auto& [slot, lease] : active_) next = std::min(next, lease.next_heartbeat);
    if (next == absl::InfiniteFuture()) {
      wake_.wait(lock);
      continue;
    }
    if (absl::Now() < next) {
      wake_.wait_until(lock, absl::ToChronoTime(next));
      continue;
    }
    std::vector<std::pair<int, ActiveLease>> due;
    for (const auto& [slot, lease] : active_) {
      if (lease.next_heartbeat <= absl::Now()) due.emplace_back(slot, lease);
    }
    lock.unlock();
    for (auto& [slot, lease] : due) {
      v1::HeartbeatRequest request;
      request.set_key(lease.key);
      request.set_token(lease.token);
      v1::HeartbeatResponse response;
      const grpc::Status status =
          stub_->Heartbeat(NewContext(lease.duration / 3).get(), request, &response);
      // A refused heartbeat means the lease is gone (expired and re-leased, or its builds
      // were cancelled): the drape runs on, but its completion will be refused.
      const bool lost = !status.ok() && !IsRetryable(status.error_code());
      if (lost) {
        core::LogLine("lease_lost")
            .Add("key", lease.key)
            .Add("token", lease.token)
            .Add("error", status.error_message());
      }
      lease.next_heartbeat =
          lost ? absl::InfiniteFuture()
               : absl::Now() + (status.ok() ? lease.duration / 3 : lease.duration / 10);
    }
    lock.lock();
    for (const auto& [slot, lease] : due) {
      auto it = active_.find(slot);
      if (it != active_.end() && it->second.token == lease.token) {
        it->second.next_heartbeat = lease.next_heartbeat;
      }
    }
  }
}

}  // namespace fitbase::workers
