#ifndef FITBASE_SERVICES_BUILD_BUILD_PLAN_H_
#define FITBASE_SERVICES_BUILD_BUILD_PLAN_H_

#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "clothing/clothing_model.h"
#include "fitbase/v1/avatar_basis.pb.h"
#include "fitbase/v1/build.pb.h"
#include "fitbase/v1/clothing_basis.pb.h"
#include "fitbase/v1/garment.pb.h"
#include "pipeline/clothing_basis_builder.h"
#include "storage/asset_store.h"

namespace fitbase::build {

// Everything a build needs, planned from the store: the garment and avatar basis it reads, and
// per size the example drapes (PlanClothingBasis, exactly as `fitbase clothing build` plans
// them). Planning is deterministic, so a restarted coordinator re-plans a build from its
// request and gets the same tasks and keys.
struct BuildPlan {
  struct Size {
    pipeline::ClothingBuildSpec spec;  // Points into the plan's garment and avatar basis.
    pipeline::ClothingPlan plan;
  };
  v1::BuildRequest request;  // Resolved: avatar basis id, methods, scale and schedule set.
  std::string tenant;
  v1::Garment garment;
  v1::AvatarBasis avatar_basis;
  std::vector<clothing::ClothingMethod> methods;
  std::vector<Size> sizes;  // In request.sizes order.
};

// The tenant's garment (NOT_FOUND when it has none of that id), its avatar basis (another id
// than the garment's is FAILED_PRECONDITION naming both), the sizes (unknown: NOT_FOUND; none or
// repeated: INVALID_ARGUMENT), methods (unknown: INVALID_ARGUMENT) and schedule.
absl::StatusOr<std::unique_ptr<const BuildPlan>> PlanBuild(const storage::AssetStore& store,
                                                           absl::string_view tenant,
                                                           const v1::BuildRequest& request);

// "<size>/<example index, 3 digits>": ids sort by size, then in example order.
std::string BuildTaskId(absl::string_view size, size_t example_index);

// The clothing basis of every size and method, from the stored drape results of the plan's
// tasks, assembled by AssembleClothingBasis (the local build's code), each kernel model's
// search on up to `threads` threads (>= 1). In size-major order.
absl::StatusOr<std::vector<v1::ClothingBasis>> AssembleBuild(const storage::AssetStore& store,
                                                             const BuildPlan& plan, int threads);

}  // namespace fitbase::build

#endif  // FITBASE_SERVICES_BUILD_BUILD_PLAN_H_
