#include "pipeline/clothing_basis_builder.h"

#include "absl/strings/str_cat.h"
#include "core/body_correspondence.h"
#include "core/content_hash.h"
#include "core/status_macros.h"
#include "proto/avatar_basis_codec.h"
#include "proto/clothing_basis_codec.h"
#include "proto/mesh_codec.h"
#include "workers/garment_drape.h"

namespace fitbase::pipeline {

absl::StatusOr<ClothingPlan> PlanClothingBasis(const ClothingBuildSpec& spec) {
  const v1::AvatarBasis& basis = *spec.avatar_basis;
  const v1::Garment& garment = *spec.garment;
  if (garment.avatar_basis_id() != basis.id()) {
    return absl::FailedPreconditionError(absl::StrCat(
        "garment ", garment.name(), " was imported on avatar basis ", garment.avatar_basis_id(),
        ", not on ", basis.id(), "; import it on this basis first"));
  }
  RETURN_IF_ERROR(workers::FindGarmentSize(garment, spec.size).status());
  ClothingPlan plan;
  ASSIGN_OR_RETURN(plan.avatar, proto::PcaBasisFromProto(basis));
  ASSIGN_OR_RETURN(plan.design,
                   core::MakeExampleDesign(plan.avatar.variances.cwiseSqrt(), spec.example_scale));
  for (int e = 0; e < plan.design.example_count(); ++e) {
    const Eigen::VectorXd body = core::ReconstructFromWeights(plan.avatar, plan.design.Weights(e));
    plan.tasks.push_back(workers::MakeDrapeTask(
        garment, spec.size, Eigen::Map<const core::Positions>(body.data(), body.size() / 3, 3),
        spec.settings, spec.schedule));
  }
  return plan;
}

absl::StatusOr<v1::ClothingBasis> AssembleClothingBasis(
    const ClothingBuildSpec& spec, const ClothingPlan& plan, core::ClothingMethod method,
    const std::vector<v1::DrapeResult>& results) {
  const v1::Garment& garment = *spec.garment;
  const int64_t vertex_count = garment.template_mesh().vertex_count();
  if (results.size() != plan.tasks.size()) {
    return absl::InvalidArgumentError(absl::StrCat("got ", results.size(), " drape results for ",
                                                   plan.tasks.size(), " example drapes"));
  }
  Eigen::MatrixXd drapes(3 * vertex_count, static_cast<Eigen::Index>(results.size()));
  for (size_t e = 0; e < results.size(); ++e) {
    if (results[e].key() != plan.tasks[e].key) {
      return absl::InvalidArgumentError(absl::StrCat("drape result ", results[e].key(),
                                                     " does not belong to example ",
                                                     plan.design.Label(static_cast<int>(e))));
    }
    ASSIGN_OR_RETURN(core::Positions positions,
                     workers::DrapeResultPositions(results[e], vertex_count));
    drapes.col(static_cast<Eigen::Index>(e)) = positions.reshaped<Eigen::RowMajor>();
  }
  ASSIGN_OR_RETURN(core::ClothingModel model,
                   core::BuildClothingModel(method, plan.design, drapes));
  ASSIGN_OR_RETURN(core::Mesh mean_body, proto::MeshFromProto(spec.avatar_basis->mean()));
  std::vector<core::Positions> example_drapes;
  std::vector<core::CorrespondenceExample> examples;
  for (Eigen::Index e = 0; e < drapes.cols(); ++e) {
    example_drapes.push_back(
        Eigen::Map<const core::Positions>(drapes.col(e).data(), vertex_count, 3));
  }
  for (Eigen::Index e = 0; e < drapes.cols(); ++e) {
    examples.push_back({&example_drapes[e], plan.design.Weights(static_cast<int>(e))});
  }
  ASSIGN_OR_RETURN(core::BodyCorrespondence correspondence,
                   core::BuildBodyCorrespondence(examples, plan.avatar,
                                                 core::Triangulate(mean_body.faces),
                                                 spec.settings.collision_offset,
                                                 spec.cleanup_anchors));

  v1::ClothingBasis message;
  message.set_garment_id(garment.id());
  message.set_size(spec.size);
  message.set_avatar_basis_id(spec.avatar_basis->id());
  proto::ClothingModelToProto(model, &message);
  proto::BodyCorrespondenceToProto(correspondence, message.mutable_correspondence());
  v1::ClothingProvenance* provenance = message.mutable_provenance();
  provenance->set_example_scale(spec.example_scale);
  provenance->set_simulator(workers::SimulatorDescription(spec.settings, spec.schedule));
  core::ContentHash id;
  id.Add(absl::string_view("clothing-basis"))
      .Add(absl::string_view(garment.id()))
      .Add(absl::string_view(spec.size))
      .Add(absl::string_view(spec.avatar_basis->id()))
      .Add(absl::string_view(message.method()))
      .Add(spec.example_scale)
      .Add(static_cast<int64_t>(spec.cleanup_anchors));
  for (size_t e = 0; e < plan.tasks.size(); ++e) {
    v1::ClothingExample* example = provenance->add_examples();
    example->set_label(plan.design.Label(static_cast<int>(e)));
    const Eigen::VectorXd weights = plan.design.Weights(static_cast<int>(e));
    example->mutable_weights()->Assign(weights.begin(), weights.end());
    example->set_drape_key(plan.tasks[e].key);
    id.Add(absl::string_view(plan.tasks[e].key));
  }
  message.set_id(id.HexDigest());
  v1::Mesh* faces = message.mutable_faces();
  *faces = garment.template_mesh();
  faces->clear_positions();
  *message.mutable_texcoords() = garment.texcoords();
  *message.mutable_face_texcoord_indices() = garment.face_texcoord_indices();
  return message;
}

}  // namespace fitbase::pipeline
