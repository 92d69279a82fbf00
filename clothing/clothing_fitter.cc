#include "clothing/clothing_fitter.h"

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
                                            FitScratch& scratch, Eigen::VectorXf& out) const {
  RETURN_IF_ERROR(CheckFitWeights(model_, weights));
  FitClothing(model_, weights, scratch.features, out);
  if (!cleanup) return 0;
  return PushOutOfBody(correspondence_, weights, scratch.cleanup, out.data());
}

absl::StatusOr<int64_t> ClothingFitter::FitToBody(const Eigen::VectorXf& weights,
                                                  std::span<const float> body, bool cleanup,
                                                  FitScratch& scratch,
                                                  Eigen::VectorXf& out) const {
  RETURN_IF_ERROR(CheckFitWeights(model_, weights));
  CleanupScratch& c = scratch.cleanup;
  RETURN_IF_ERROR(GatherBodyPoints(correspondence_, body, c.own_body));
  FitClothing(model_, weights, scratch.features, out);
  BodyPointsOfWeights(correspondence_, weights, c.body);
  FollowBody(correspondence_, c.body, c.own_body, c, out.data());
  if (!cleanup) return 0;
  return PushOutOfBodyPoints(correspondence_, c.own_body, c.anchor_rows, c, out.data());
}

}  // namespace fitbase::clothing
