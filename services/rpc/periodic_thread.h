#ifndef FITBASE_SERVICES_RPC_PERIODIC_THREAD_H_
#define FITBASE_SERVICES_RPC_PERIODIC_THREAD_H_

#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

#include "absl/time/time.h"

namespace fitbase::rpc {

// Calls `tick` every `period` on a thread of its own until Stop() or destruction, which
// interrupt the wait at once (a server's lease reaper, a secondary's catch-up).
class PeriodicThread {
 public:
  PeriodicThread(absl::Duration period, std::function<void()> tick)
      : period_(period), tick_(std::move(tick)), thread_([this] { Run(); }) {}
  ~PeriodicThread() { Stop(); }
  PeriodicThread(const PeriodicThread&) = delete;
  PeriodicThread& operator=(const PeriodicThread&) = delete;

  void Stop() {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
  }

 private:
  void Run() {
    std::unique_lock lock(mutex_);
    while (!wake_.wait_for(lock, absl::ToChronoNanoseconds(period_), [&] { return stopping_; })) {
      lock.unlock();
      tick_();
      lock.lock();
    }
  }

  const absl::Duration period_;
  const std::function<void()> tick_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread thread_;  // Last: starts once the members above exist.
};

}  // namespace fitbase::rpc

#endif  // FITBASE_SERVICES_RPC_PERIODIC_THREAD_H_
