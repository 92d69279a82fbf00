#ifndef FITBASE_PIPELINE_CLOTHING_BASIS_BUILDER_H_
#define FITBASE_PIPELINE_CLOTHING_BASIS_BUILDER_H_

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "clothing/clothing_model.h"
#include "core/pca_basis.h"
#include "fitbase/v1/avatar_basis.pb.h"
#include "fitbase/v1/clothing_basis.pb.h"
#include "fitbase/v1/garment.pb.h"
#include "workers/drape_task.h"

namespace fitbase::pipeline {

// What a clothing basis is built from. The pointers must outlive the plan and its tasks.
struct ClothingBuildSpec {
  const v1::AvatarBasis* avatar_basis = nullptr;
  const v1::Garment* garment = nullptr;
  std::string size;
  double example_scale = 1.0;  // s: examples at mu +- s sigma_k phi_k.
  // Anchors per garment vertex of the fit-time collision clean-up (see BodyCorrespondence).
  int cleanup_anchors = 4;
  // Bodies drawn from the avatar basis's population (w_k ~ N(0, sigma_k^2), cut at 3 sigma_k),
  // each draped, to train the `kernel` method; 0 for the other methods, which ignore them.
  int sampled_drapes = 0;
  uint64_t sample_seed = 1;
  workers::ClothSettings settings;
  workers::DrapeSchedule schedule;
  // Threads of the kernel model's search (clothing::KernelBuildOptions::threads); the basis is
  // the same bytes for any count.
  int model_threads = 1;
};

// The drapes of one garment size: the 2N + 1 example avatars of the design, then the sampled
// bodies, each a content-addressed drape task. Every method builds from the same tasks, so one
// set of drapes serves them all, and the distributed build runs exactly these.
struct ClothingPlan {
  core::PcaBasis avatar;
  clothing::ExampleDesign design;
  Eigen::MatrixXd sample_weights;         // N x sampled_drapes, m.
  std::vector<workers::DrapeTask> tasks;  // ExampleDesign order, then the samples'.
  std::string TaskLabel(size_t task) const;  // "mean", "+3", "-3", ..., "sample-17".
  Eigen::VectorXd TaskWeights(size_t task) const;  // N, the task's avatar weights, m.
};

// Errors: a garment imported on another avatar basis (FAILED_PRECONDITION naming both ids),
// an unknown size (NOT_FOUND listing the garment's sizes), a bad basis or scale, a sample
// count outside [0, kMaxSampledDrapes].
absl::StatusOr<ClothingPlan> PlanClothingBasis(const ClothingBuildSpec& spec);

inline constexpr int kMaxSampledDrapes = 4096;

// The clothing basis of `method` from the plan's drape results (results[i] for tasks[i]),
// with the fit-time body correspondence and the garment's topology. `kernel` learns from the
// sampled drapes too (FAILED_PRECONDITION if the plan has none); the other methods use the
// design's examples only, so their bytes do not depend on the samples. Its id hashes the
// garment, size, avatar basis, method and every drape key it uses, so equal inputs give the
// same bytes. InvalidArgument when a result's key or vertex count does not match its task.
absl::StatusOr<v1::ClothingBasis> AssembleClothingBasis(
    const ClothingBuildSpec& spec, const ClothingPlan& plan, clothing::ClothingMethod method,
    const std::vector<v1::DrapeResult>& results);

}  // namespace fitbase::pipeline

#endif  // FITBASE_PIPELINE_CLOTHING_BASIS_BUILDER_H_
