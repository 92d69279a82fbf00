#ifndef FITBASE_SERVICES_FIT_CALL_QUEUE_H_
#define FITBASE_SERVICES_FIT_CALL_QUEUE_H_

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "absl/status/status.h"

namespace fitbase::fit {

// The fit service's admission: at most `capacity` calls at once, run in arrival order by
// `threads` threads of its own; a call beyond the capacity is refused at once. Past
// saturation the excess must be answered rather than left to queue: gRPC's callback threads
// would otherwise hold every arriving call, and each served call would wait behind all of
// them. Running the work here keeps gRPC's threads to the cheap part (reading, refusing,
// writing), so the queue forms where it is bounded.
class CallQueue {
 public:
  CallQueue(int threads, int capacity);
  // Runs what is queued, then joins the threads.
  ~CallQueue();
  CallQueue(const CallQueue&) = delete;
  CallQueue& operator=(const CallQueue&) = delete;

  // Queues the call, or returns false without running it when `capacity` calls are running or
  // queued. `answer` gets `work`'s status once the call no longer counts against the capacity,
  // so a caller that has its answer may call again at once.
  bool TryRun(std::function<absl::Status()> work,
              std::function<void(const absl::Status&)> answer);

  int capacity() const { return capacity_; }

 private:
  void Work();

  const int capacity_;
  std::mutex mutex_;
  std::condition_variable wake_;
  struct Call {
    std::function<absl::Status()> work;
    std::function<void(const absl::Status&)> answer;
  };
  std::deque<Call> queued_;
  int admitted_ = 0;  // Queued or running.
  bool stopping_ = false;
  std::vector<std::thread> threads_;  // Last: started once the members above exist.
};

}  // namespace fitbase::fit

#endif  // FITBASE_SERVICES_FIT_CALL_QUEUE_H_
