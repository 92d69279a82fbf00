#include "core/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace fitbase::core {

void ParallelFor(size_t count, int threads, absl::FunctionRef<void(size_t)> body) {
  if (count == 0) return;
  std::atomic<size_t> next{0};
  const auto drain = [&] {
    for (size_t i = next++; i < count; i = next++) body(i);
  };
  const size_t helper_count = std::min(count, static_cast<size_t>(std::max(threads, 1))) - 1;
  std::vector<std::thread> helpers;
  helpers.reserve(helper_count);
  for (size_t j = 0; j < helper_count; ++j) helpers.emplace_back(drain);
  drain();
  for (std::thread& helper : helpers) helper.join();
}

}  // namespace fitbase::core
