#ifndef FITBASE_PIPELINE_AVATAR_PROJECTION_H_
#define FITBASE_PIPELINE_AVATAR_PROJECTION_H_

#include <filesystem>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "core/mesh.h"
#include "core/pca_basis.h"
#include "fitbase/v1/avatar.pb.h"
#include "fitbase/v1/avatar_basis.pb.h"

namespace fitbase::pipeline {

// An avatar basis as stored and as the math uses it.
struct LoadedAvatarBasis {
  v1::AvatarBasis message;
  core::PcaBasis pca;
};

absl::StatusOr<LoadedAvatarBasis> LoadAvatarBasis(const std::filesystem::path& path);

// The avatar's weights on the basis (m) with its reconstruction error (mm). The avatar must
// have the basis's vertex count (InvalidArgument naming both otherwise).
absl::StatusOr<v1::AvatarWeights> ProjectAvatar(const LoadedAvatarBasis& basis,
                                                const core::Mesh& avatar);

// The weights as numbers, checked: `components` of them (the count of avatar basis
// `basis_id`), all finite. InvalidArgument naming the problem otherwise.
absl::StatusOr<Eigen::VectorXd> CheckedWeights(const v1::AvatarWeights& weights,
                                               int64_t components, absl::string_view basis_id);

// The body of the weights, mean + components x weights: the body a fit is made for and the fit
// service returns with it, B x 3 (m). weights: one finite weight per component of the basis
// (m), checked by the caller.
core::Positions BodyOfWeights(const LoadedAvatarBasis& basis, const Eigen::VectorXd& weights);

}  // namespace fitbase::pipeline

#endif  // FITBASE_PIPELINE_AVATAR_PROJECTION_H_
