#include "services/fit/call_queue.h"

#include <algorithm>

namespace fitbase::fit {

CallQueue::CallQueue(int threads, int capacity) : capacity_(std::max(capacity, 0)) {
  for (int i = 0; i < std::max(threads, 1); ++i) threads_.emplace_back([this] { Work(); });
}

CallQueue::~CallQueue() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

bool CallQueue::TryRun(std::function<absl::Status()> work,
                       std::function<void(const absl::Status&)> answer) {
  {
    std::lock_guard lock(mutex_);
    if (admitted_ >= capacity_) return false;
    ++admitted_;
    queued_.push_back({std::move(work), std::move(answer)});
  }
  wake_.notify_one();
  return true;
}

void CallQueue::Work() {
  std::unique_lock lock(mutex_);
  while (true) {
    wake_.wait(lock, [&] { return stopping_ || !queued_.empty(); });
    // Queued calls still run when stopping: each must answer its caller.
    if (queued_.empty()) return;
    Call call = std::move(queued_.front());
    queued_.pop_front();
    lock.unlock();
    const absl::Status status = call.work();
    lock.lock();
    --admitted_;
    lock.unlock();
    call.answer(status);
    lock.lock();
  }
}

}  // namespace fitbase::fit
