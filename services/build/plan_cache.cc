#include "services/build/plan_cache.h"

#include "core/status_macros.h"

namespace fitbase::build {

absl::StatusOr<std::shared_ptr<const BuildPlan>> PlanCache::Get(const std::string& build_id,
                                                                Planner plan) {
  std::lock_guard lock(mutex_);
  for (auto it = plans_.begin(); it != plans_.end(); ++it) {
    if (it->first != build_id) continue;
    plans_.splice(plans_.begin(), plans_, it);
    return plans_.front().second;
  }
  ASSIGN_OR_RETURN(std::shared_ptr<const BuildPlan> planned, plan());
  PutLocked(build_id, planned);
  return planned;
}

void PlanCache::Put(const std::string& build_id, std::shared_ptr<const BuildPlan> plan) {
  std::lock_guard lock(mutex_);
  PutLocked(build_id, std::move(plan));
}

void PlanCache::PutLocked(const std::string& build_id, std::shared_ptr<const BuildPlan> plan) {
  std::erase_if(plans_, [&](const auto& entry) { return entry.first == build_id; });
  plans_.emplace_front(build_id, std::move(plan));
  while (plans_.size() > capacity_) plans_.pop_back();
}

}  // namespace fitbase::build
