#ifndef FITBASE_SERVICES_FIT_BYTE_LRU_CACHE_H_
#define FITBASE_SERVICES_FIT_BYTE_LRU_CACHE_H_

#include <cstddef>
#include <list>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>

#include "absl/container/flat_hash_map.h"
#include "absl/time/time.h"

namespace fitbase::fit {

// A thread-safe least-recently-used cache bounded by the bytes its values hold. Values are
// shared, so an evicted value stays alive for the calls still using it. Each entry keeps the
// time it was last confirmed current, for callers that re-check their source now and then.
template <typename V>
class ByteLruCache {
 public:
  struct Entry {
    std::shared_ptr<const V> value;
    size_t bytes = 0;
    absl::Time checked;
  };

  explicit ByteLruCache(size_t max_bytes) : max_bytes_(max_bytes) {}

  std::optional<Entry> Get(const std::string& key) {
    std::lock_guard lock(mutex_);
    auto it = index_.find(key);
    if (it == index_.end()) return std::nullopt;
    order_.splice(order_.begin(), order_, it->second);
    return it->second->second;
  }

  // Inserts or replaces; evicts the least recently used entries beyond the budget (never the
  // one just put, so a value larger than the budget is still served, then evicted next time).
  void Put(const std::string& key, Entry entry) {
    std::lock_guard lock(mutex_);
    if (auto it = index_.find(key); it != index_.end()) {
      bytes_ -= it->second->second.bytes;
      order_.erase(it->second);
      index_.erase(it);
    }
    bytes_ += entry.bytes;
    order_.emplace_front(key, std::move(entry));
    index_[key] = order_.begin();
    while (bytes_ > max_bytes_ && order_.size() > 1) {
      bytes_ -= order_.back().second.bytes;
      index_.erase(order_.back().first);
      order_.pop_back();
    }
  }

  // Marks the entry confirmed current at `when`.
  void Touch(const std::string& key, absl::Time when) {
    std::lock_guard lock(mutex_);
    if (auto it = index_.find(key); it != index_.end()) it->second->second.checked = when;
  }

 private:
  using List = std::list<std::pair<std::string, Entry>>;
  const size_t max_bytes_;
  mutable std::mutex mutex_;
  List order_;  // Most recently used first.
  absl::flat_hash_map<std::string, typename List::iterator> index_;
  size_t bytes_ = 0;
};

}  // namespace fitbase::fit

#endif  // FITBASE_SERVICES_FIT_BYTE_LRU_CACHE_H_
