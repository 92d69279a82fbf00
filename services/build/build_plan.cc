#include "services/build/build_plan.h"

#include <algorithm>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "core/status_macros.h"
#include "workers/drape.h"

namespace fitbase::build {
namespace {

// Bounds on a request's schedule: a build is thousands of drapes, so a typo must not make
// each one a hundred times longer.
constexpr uint32_t kMaxScheduleSteps = 10000;
constexpr double kMaxExampleScale = 4.0;

absl::Status ResolveRequest(v1::BuildRequest& request, const v1::Garment& garment) {
  if (request.garment_id().empty()) return absl::InvalidArgumentError("garment_id is empty");
  if (request.avatar_basis_id().empty()) {
    request.set_avatar_basis_id(garment.avatar_basis_id());
  } else if (request.avatar_basis_id() != garment.avatar_basis_id()) {
    return absl::FailedPreconditionError(absl::StrCat(
        "garment ", garment.id(), " was imported on avatar basis ", garment.avatar_basis_id(),
        ", not ", request.avatar_basis_id(), "; import it on that basis to build for it"));
  }
  if (request.sizes().empty()) return absl::InvalidArgumentError("a build needs sizes");
  std::vector<std::string> sizes(request.sizes().begin(), request.sizes().end());
  std::sort(sizes.begin(), sizes.end());
  if (std::adjacent_find(sizes.begin(), sizes.end()) != sizes.end()) {
    return absl::InvalidArgumentError(
        absl::StrCat("sizes repeat: ", absl::StrJoin(request.sizes(), ",")));
  }
  if (request.methods().empty()) request.add_methods("linear");
  if (request.example_scale() == 0) request.set_example_scale(1.0);
  if (!(request.example_scale() > 0 && request.example_scale() <= kMaxExampleScale)) {
    return absl::InvalidArgumentError(absl::StrCat("example_scale ", request.example_scale(),
                                                   " is outside (0, ", kMaxExampleScale, "]"));
  }
  const bool kernel =
      std::find(request.methods().begin(), request.methods().end(), "kernel") !=
      request.methods().end();
  if (kernel && request.sampled_drapes() == 0) {
    return absl::InvalidArgumentError(
        "the kernel method learns from drapes of sampled bodies; set sampled_drapes");
  }
  if (!kernel) request.set_sampled_drapes(0);
  if (request.sampled_drapes() > static_cast<uint32_t>(pipeline::kMaxSampledDrapes)) {
    return absl::InvalidArgumentError(absl::StrCat("sampled_drapes ", request.sampled_drapes(),
                                                   " is above ", pipeline::kMaxSampledDrapes));
  }
  if (request.sample_seed() == 0) request.set_sample_seed(1);
  const workers::DrapeSchedule defaults;
  if (request.homotopy_steps() == 0) request.set_homotopy_steps(defaults.homotopy_steps);
  if (request.relax_steps() == 0) request.set_relax_steps(defaults.relax_steps);
  if (request.homotopy_steps() > kMaxScheduleSteps || request.relax_steps() > kMaxScheduleSteps) {
    return absl::InvalidArgumentError(
        absl::StrCat("homotopy_steps and relax_steps are at most ", kMaxScheduleSteps));
  }
  return absl::OkStatus();
}

}  // namespace

std::string BuildTaskId(absl::string_view size, size_t example_index) {
  return absl::StrFormat("%s/%03d", size, example_index);
}

absl::StatusOr<std::unique_ptr<const BuildPlan>> PlanBuild(const storage::AssetStore& store,
                                                           absl::string_view tenant,
                                                           const v1::BuildRequest& request) {
  auto plan = std::make_unique<BuildPlan>();
  plan->tenant = std::string(tenant);
  plan->request = request;
  ASSIGN_OR_RETURN(std::string garment_bytes, store.GetGarment(tenant, request.garment_id()));
  if (!plan->garment.ParseFromString(garment_bytes)) {
    return absl::DataLossError(absl::StrCat("stored garment ", request.garment_id(),
                                            " does not parse"));
  }
  RETURN_IF_ERROR(ResolveRequest(plan->request, plan->garment));
  ASSIGN_OR_RETURN(std::string basis_bytes,
                   store.GetAvatarBasis(plan->request.avatar_basis_id()));
  if (!plan->avatar_basis.ParseFromString(basis_bytes)) {
    return absl::DataLossError(absl::StrCat("stored avatar basis ",
                                            plan->request.avatar_basis_id(), " does not parse"));
  }
  for (const std::string& method : plan->request.methods()) {
    ASSIGN_OR_RETURN(clothing::ClothingMethod parsed, clothing::ParseClothingMethod(method));
    plan->methods.push_back(parsed);
  }
  plan->sizes.reserve(static_cast<size_t>(plan->request.sizes_size()));
  for (const std::string& size : plan->request.sizes()) {
    pipeline::ClothingBuildSpec spec{
        .avatar_basis = &plan->avatar_basis,
        .garment = &plan->garment,
        .size = size,
        .example_scale = plan->request.example_scale(),
        .sampled_drapes = static_cast<int>(plan->request.sampled_drapes()),
        .sample_seed = plan->request.sample_seed(),
        .settings = {},
        .schedule = {.homotopy_steps = static_cast<int>(plan->request.homotopy_steps()),
                     .relax_steps = static_cast<int>(plan->request.relax_steps())}};
    ASSIGN_OR_RETURN(pipeline::ClothingPlan size_plan, pipeline::PlanClothingBasis(spec));
    plan->sizes.push_back({std::move(spec), std::move(size_plan)});
  }
  return std::unique_ptr<const BuildPlan>(std::move(plan));
}

absl::StatusOr<std::vector<v1::ClothingBasis>> AssembleBuild(const storage::AssetStore& store,
                                                             const BuildPlan& plan, int threads) {
  std::vector<v1::ClothingBasis> bases;
  for (const BuildPlan::Size& size : plan.sizes) {
    pipeline::ClothingBuildSpec spec = size.spec;
    spec.model_threads = threads;
    std::vector<v1::DrapeResult> results(size.plan.tasks.size());
    for (size_t i = 0; i < results.size(); ++i) {
      ASSIGN_OR_RETURN(std::string bytes, store.GetDrapeResult(size.plan.tasks[i].key));
      if (!results[i].ParseFromString(bytes)) {
        return absl::DataLossError(
            absl::StrCat("stored drape result ", size.plan.tasks[i].key, " does not parse"));
      }
    }
    for (clothing::ClothingMethod method : plan.methods) {
      ASSIGN_OR_RETURN(v1::ClothingBasis basis,
                       pipeline::AssembleClothingBasis(spec, size.plan, method, results));
      bases.push_back(std::move(basis));
    }
  }
  return bases;
}

}  // namespace fitbase::build
