#include "core/parallel_for.h"

#include <atomic>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

TEST(ParallelForTest, CallsTheBodyOnceForEveryIndex) {
  for (const int threads : {-1, 0, 1, 2, 8}) {
    for (const size_t count : {size_t{0}, size_t{1}, size_t{3}, size_t{1000}}) {
      std::vector<std::atomic<int>> calls(count);
      ParallelFor(count, threads, [&](size_t i) { ++calls[i]; });
      for (size_t i = 0; i < count; ++i) {
        ASSERT_EQ(calls[i], 1) << "index " << i << " of " << count << ", " << threads << " threads";
      }
    }
  }
}

TEST(ParallelForTest, OneThreadRunsInOrderOnTheCaller) {
  std::vector<size_t> order;
  const std::thread::id caller = std::this_thread::get_id();
  bool elsewhere = false;
  ParallelFor(50, 1, [&](size_t i) {
    order.push_back(i);
    elsewhere = elsewhere || std::this_thread::get_id() != caller;
  });
  ASSERT_EQ(order.size(), 50u);
  for (size_t i = 0; i < order.size(); ++i) EXPECT_EQ(order[i], i);
  EXPECT_FALSE(elsewhere);
}

// Two items that each wait for the other to start can only finish on two threads at once: the
// test fails by timing out if the helper thread never starts.
TEST(ParallelForTest, RunsItemsAtTheSameTimeOnSeveralThreads) {
  std::atomic<int> started{0};
  std::mutex mutex;
  std::set<std::thread::id> ids;
  ParallelFor(2, 2, [&](size_t) {
    ++started;
    while (started < 2) std::this_thread::yield();
    std::lock_guard<std::mutex> lock(mutex);
    ids.insert(std::this_thread::get_id());
  });
  EXPECT_EQ(ids.size(), 2u);
}

TEST(ParallelForTest, NeverStartsMoreThreadsThanItems) {
  std::mutex mutex;
  std::set<std::thread::id> ids;
  ParallelFor(1, 8, [&](size_t) {
    std::lock_guard<std::mutex> lock(mutex);
    ids.insert(std::this_thread::get_id());
  });
  ASSERT_EQ(ids.size(), 1u);
  EXPECT_EQ(*ids.begin(), std::this_thread::get_id());
}

}  // namespace
}  // namespace fitbase::core
