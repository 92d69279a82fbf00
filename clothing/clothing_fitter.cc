#include "clothing/clothing_fitter.h"

#include "absl/strings/str_cat.h"
#include "core/status_macros.h"

namespace fitbase::clothing {

absl::StatusOr<ClothingFitter> ClothingFitter::Create(ClothingModel model,
                                                      BodyCorrespondence correspondence) {
  RETURN_IF_ERROR(ValidateClothingModel(model));
  RETURN_IF_ERROR(ValidateBodyCorrespondence(correspondence, model.vertex_count(),
                                             model.component_count));
  return ClothingFitter(std::move(model), std::move(correspondence));
}

absl::StatusOr<int64_t> ClothingFitter::Fit(const Eigen::VectorXf& weights, bool cleanup,
                                            FitScratch& scratch, Eigen::VectorXf& out,
                                            const AvatarMesh& avatar) const {
  RETURN_IF_ERROR(CheckFitWeights(model_, weights));
  if (avatar.basis != nullptr) {
    if (avatar.triangles == nullptr || avatar.triangles->rows() == 0) {
      return absl::InvalidArgumentError("the avatar basis comes without triangles");
    }
    if (avatar.basis->components.cols() != weights.size()) {
      return absl::InvalidArgumentError(
          absl::StrCat("the avatar basis has ", avatar.basis->components.cols(),
                       " components; the fit has ", weights.size(), " weights"));
    }
  }
  FitClothing(model_, weights, scratch.features, out);
  if (!cleanup) return 0;
  if (avatar.basis == nullptr) {
    return PushOutOfBody(correspondence_, weights, scratch.cleanup, out.data());
  }
  CleanupScratch& c = scratch.cleanup;
  BodyPointsOfWeights(correspondence_, weights, c.body);
  const BodyMesh of_weights{{}, avatar.basis, &weights, avatar.triangles};
  return PushOutOfBodyPoints(correspondence_, c.body, {}, &of_weights, c, out.data());
}

absl::StatusOr<int64_t> ClothingFitter::FitToBody(const Eigen::VectorXf& weights,
                                                  const BodyMesh& body, bool cleanup,
                                                  FitScratch& scratch,
                                                  Eigen::VectorXf& out) const {
  RETURN_IF_ERROR(CheckFitWeights(model_, weights));
  if (body.triangles == nullptr || body.triangles->rows() == 0) {
    return absl::InvalidArgumentError("the body mesh has no triangles");
  }
  CleanupScratch& c = scratch.cleanup;
  RETURN_IF_ERROR(GatherBodyPoints(correspondence_, body.positions, c.own_body));
  FitClothing(model_, weights, scratch.features, out);
  BodyPointsOfWeights(correspondence_, weights, c.body);
  FollowBody(correspondence_, c.body, c.own_body, c, out.data());
  if (!cleanup) return 0;
  return PushOutOfBodyPoints(correspondence_, c.own_body, c.anchor_rows, &body, c, out.data());
}

}  // namespace fitbase::clothing
