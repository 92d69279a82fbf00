#include "pipeline/avatar_projection.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "proto/avatar_basis_codec.h"
#include "proto/message_file.h"

namespace fitbase::pipeline {

absl::StatusOr<LoadedAvatarBasis> LoadAvatarBasis(const std::filesystem::path& path) {
  LoadedAvatarBasis basis;
  RETURN_IF_ERROR(proto::ReadMessageFile(path, &basis.message));
  ASSIGN_OR_RETURN(basis.pca, proto::PcaBasisFromProto(basis.message));
  return basis;
}

absl::StatusOr<Eigen::VectorXd> CheckedWeights(const v1::AvatarWeights& weights,
                                               int64_t components, absl::string_view basis_id) {
  if (weights.weights_size() != components) {
    return absl::InvalidArgumentError(absl::StrCat("the weights have ", weights.weights_size(),
                                                   " components; avatar basis ", basis_id,
                                                   " has ", components));
  }
  Eigen::VectorXd w(components);
  for (int k = 0; k < components; ++k) {
    if (!std::isfinite(weights.weights(k))) {
      return absl::InvalidArgumentError(absl::StrCat("weight ", k, " is not finite"));
    }
    w(k) = weights.weights(k);
  }
  return w;
}

absl::StatusOr<v1::AvatarWeights> ProjectAvatar(const LoadedAvatarBasis& basis,
                                                const core::Mesh& avatar) {
  const Eigen::Index dims = basis.pca.mean.size();
  if (avatar.positions.size() != dims) {
    return absl::InvalidArgumentError(absl::StrCat("avatar has ", avatar.vertex_count(),
                                                   " vertices; basis ", basis.message.id(),
                                                   " takes ", dims / 3));
  }
  const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(avatar.positions.data(), dims);
  const Eigen::VectorXd weights = core::ProjectOntoBasis(basis.pca, x);
  const core::ReconstructionError error =
      core::MeasureReconstructionError(x, core::ReconstructFromWeights(basis.pca, weights));
  v1::AvatarWeights result;
  result.set_basis_id(basis.message.id());
  result.mutable_weights()->Assign(weights.begin(), weights.end());
  result.set_mean_error_mm(error.mean_mm);
  result.set_max_error_mm(error.max_mm);
  return result;
}

core::Positions BodyOfWeights(const LoadedAvatarBasis& basis, const Eigen::VectorXd& weights) {
  const Eigen::VectorXd flat = core::ReconstructFromWeights(basis.pca, weights);
  return Eigen::Map<const core::Positions>(flat.data(), flat.size() / 3, 3);
}

}  // namespace fitbase::pipeline
