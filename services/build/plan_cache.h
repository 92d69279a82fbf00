#ifndef FITBASE_SERVICES_BUILD_PLAN_CACHE_H_
#define FITBASE_SERVICES_BUILD_PLAN_CACHE_H_

#include <cstddef>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include "absl/functional/function_ref.h"
#include "absl/status/statusor.h"
#include "services/build/build_plan.h"

namespace fitbase::build {

// Build plans by build id, the `capacity` most recently used. A plan holds its garment, its
// avatar basis (twice: the message and the PCA basis of each size) and every example body
// (13,380 x 3 doubles, 321 KB each): about 40 MB for two sizes on a basis of 20 components.
// A coordinator with thousands of builds queued therefore keeps only the plans being leased
// and assembled, and plans a build again when its turn comes (PlanBuild is deterministic).
// Thread-safe.
class PlanCache {
 public:
  explicit PlanCache(size_t capacity) : capacity_(capacity) {}

  using Planner = absl::FunctionRef<absl::StatusOr<std::unique_ptr<const BuildPlan>>()>;

  // The cached plan of `build_id`, else `plan()`'s, then cached. Planning holds the cache, so
  // a burst of leases of one build plans it once.
  absl::StatusOr<std::shared_ptr<const BuildPlan>> Get(const std::string& build_id,
                                                       Planner plan);
  void Put(const std::string& build_id, std::shared_ptr<const BuildPlan> plan);

 private:
  void PutLocked(const std::string& build_id, std::shared_ptr<const BuildPlan> plan);

  const size_t capacity_;
  std::mutex mutex_;
  std::list<std::pair<std::string, std::shared_ptr<const BuildPlan>>> plans_;  // Newest first.
};

}  // namespace fitbase::build

#endif  // FITBASE_SERVICES_BUILD_PLAN_CACHE_H_
