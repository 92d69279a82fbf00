#include "pipeline/avatar_basis_builder.h"

#include "body/body_model.h"
#include "core/content_hash.h"
#include "core/status_macros.h"
#include "proto/avatar_basis_codec.h"

namespace fitbase::pipeline {
namespace {

// Bump when the decomposition or selection changes what a given input produces.
constexpr absl::string_view kAlgorithm = "fitbase-avatar-pca-v1";

v1::ComponentSelection SelectionToProto(const core::ComponentSelection& selection) {
  v1::ComponentSelection message;
  switch (selection.rule) {
    case core::ComponentSelection::Rule::kMaxMeanErrorMm:
      message.set_max_mean_error_mm(selection.max_mean_error_mm);
      break;
    case core::ComponentSelection::Rule::kCount:
      message.set_component_count(static_cast<uint32_t>(selection.count));
      break;
    case core::ComponentSelection::Rule::kVarianceFraction:
      message.set_variance_fraction(selection.variance_fraction);
      break;
  }
  return message;
}

}  // namespace

absl::StatusOr<v1::AvatarBasis> BuildAvatarBasis(const Population& population,
                                                 const core::ComponentSelection& selection) {
  ASSIGN_OR_RETURN(core::PcaBasis pca, core::BuildPcaBasis(population.samples, selection));
  v1::AvatarBasis basis = proto::AvatarBasisToProto(pca, body::kBodyTopologyId, population.faces);
  *basis.mutable_selection() = SelectionToProto(selection);
  *basis.mutable_population() = population.provenance;

  const Eigen::MatrixXf avatars = population.samples.cast<float>();
  const std::string avatars_sha256 =
      core::ContentHash()
          .Add(std::span<const float>(avatars.data(), static_cast<size_t>(avatars.size())))
          .HexDigest();
  basis.mutable_population()->set_avatars_sha256(avatars_sha256);
  basis.set_id(core::ContentHash()
                   .Add(kAlgorithm)
                   .Add(body::kBodyTopologyId)
                   .Add(avatars_sha256)
                   .Add(basis.selection().SerializeAsString())
                   .HexDigest());
  return basis;
}

}  // namespace fitbase::pipeline
