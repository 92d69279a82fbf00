#ifndef FITBASE_PIPELINE_AVATAR_BASIS_BUILDER_H_
#define FITBASE_PIPELINE_AVATAR_BASIS_BUILDER_H_

#include "absl/status/statusor.h"
#include "core/pca_basis.h"
#include "fitbase/v1/avatar_basis.pb.h"
#include "pipeline/population_folder.h"

namespace fitbase::pipeline {

// PCA over the population's avatars. The id is a SHA-256 over the training avatars (float32,
// in order) and the selection rule: the same population and settings give the same id
// whatever the floating-point details of the machine that ran the decomposition.
absl::StatusOr<v1::AvatarBasis> BuildAvatarBasis(const Population& population,
                                                 const core::ComponentSelection& selection);

}  // namespace fitbase::pipeline

#endif  // FITBASE_PIPELINE_AVATAR_BASIS_BUILDER_H_
