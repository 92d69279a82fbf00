#include "proto/avatar_basis_codec.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "proto/mesh_codec.h"

namespace fitbase::proto {

v1::AvatarBasis AvatarBasisToProto(const core::PcaBasis& basis, absl::string_view topology_id,
                                   const core::PolygonFaces& faces) {
  v1::AvatarBasis message;
  message.set_topology_id(std::string(topology_id));
  const Eigen::Index dims = basis.mean.size();
  core::Mesh mean{.topology_id = std::string(topology_id),
                  .positions = Eigen::Map<const core::Positions>(basis.mean.data(), dims / 3, 3),
                  .faces = faces};
  *message.mutable_mean() = MeshToProto(mean);
  const Eigen::Index n = basis.components.cols();
  message.set_component_count(static_cast<uint32_t>(n));
  auto* components = message.mutable_components();
  components->Reserve(static_cast<int>(dims * n));
  for (Eigen::Index k = 0; k < n; ++k) {
    for (Eigen::Index i = 0; i < dims; ++i) {
      components->AddAlreadyReserved(static_cast<float>(basis.components(i, k)));
    }
  }
  message.mutable_variances()->Assign(basis.variances.begin(), basis.variances.end());
  message.mutable_explained_variance_ratio()->Assign(basis.explained_variance_ratio.begin(),
                                                      basis.explained_variance_ratio.end());
  message.set_total_variance(basis.total_variance);
  message.set_training_mean_error_mm(basis.training_error.mean_mm);
  message.set_training_max_error_mm(basis.training_error.max_mm);
  return message;
}

absl::StatusOr<core::PcaBasis> PcaBasisFromProto(const v1::AvatarBasis& message) {
  ASSIGN_OR_RETURN(core::Mesh mean, MeshFromProto(message.mean()));
  const int64_t dims = 3 * mean.vertex_count();
  const int64_t n = message.component_count();
  if (dims == 0 || n == 0) return absl::InvalidArgumentError("avatar basis is empty");
  if (message.components_size() != n * dims || message.variances_size() != n ||
      message.explained_variance_ratio_size() != n) {
    return absl::InvalidArgumentError(absl::StrCat(
        "avatar basis ", message.id(), " is inconsistent: ", n, " components of size ", dims,
        " need ", n * dims, " values, found ", message.components_size(), " values, ",
        message.variances_size(), " variances, ", message.explained_variance_ratio_size(),
        " explained-variance ratios"));
  }
  core::PcaBasis basis;
  basis.mean = Eigen::Map<const Eigen::VectorXd>(mean.positions.data(), dims);
  basis.components =
      Eigen::Map<const Eigen::MatrixXf>(message.components().data(), dims, n).cast<double>();
  if (!basis.components.allFinite()) {
    return absl::InvalidArgumentError(
        absl::StrCat("avatar basis ", message.id(), " has non-finite components"));
  }
  basis.variances = Eigen::Map<const Eigen::VectorXd>(message.variances().data(), n);
  basis.explained_variance_ratio =
      Eigen::Map<const Eigen::VectorXd>(message.explained_variance_ratio().data(), n);
  if (!basis.variances.allFinite() || (basis.variances.array() <= 0).any()) {
    return absl::InvalidArgumentError(
        absl::StrCat("avatar basis ", message.id(), " has a non-positive or non-finite variance"));
  }
  if (!basis.explained_variance_ratio.allFinite() || !std::isfinite(message.total_variance())) {
    return absl::InvalidArgumentError(absl::StrCat(
        "avatar basis ", message.id(), " has a non-finite explained variance or total variance"));
  }
  basis.total_variance = message.total_variance();
  basis.training_error = {message.training_mean_error_mm(), message.training_max_error_mm()};
  basis.sample_count = static_cast<int>(message.population().count());
  return basis;
}

}  // namespace fitbase::proto
