#ifndef FITBASE_CLOTHING_CLOTHING_FITTER_H_
#define FITBASE_CLOTHING_CLOTHING_FITTER_H_

#include <span>

#include "Eigen/Core"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "clothing/body_correspondence.h"
#include "clothing/clothing_model.h"

namespace fitbase::clothing {

// Per-thread working memory of ClothingFitter::Fit, so a fit allocates nothing once warm.
struct FitScratch {
  Eigen::VectorXf features;
  CleanupScratch cleanup;
};

// The online fit of one garment size: the clothing model evaluated at a customer's avatar
// weights, then (optionally) the collision clean-up. Immutable after Create, so one fitter
// serves any number of threads, each with its own FitScratch.
class ClothingFitter {
 public:
  // The model and correspondence must agree in vertex and component counts.
  static absl::StatusOr<ClothingFitter> Create(ClothingModel model,
                                               BodyCorrespondence correspondence);

  // weights: N (m), checked; out: 3V floats (m), xyz interleaved, the template's vertex order.
  // The clean-up clears the body of the weights and asks it, under the garment, about its deep
  // pushes (PushOutOfBodyPoints). Returns how many vertices the clean-up moved.
  absl::StatusOr<int64_t> Fit(const Eigen::VectorXf& weights, bool cleanup, FitScratch& scratch,
                              Eigen::VectorXf& out) const;

  // As Fit, for the customer's own mesh instead of the body of the weights: body, 3B floats
  // (m, xyz interleaved) in the avatar topology, the mesh `weights` were projected from. The
  // fitted garment follows what the projection left out of the body (FollowBody), and the
  // clean-up clears `body`, asking it under the garment about the deep pushes. InvalidArgument
  // as GatherBodyPoints.
  absl::StatusOr<int64_t> FitToBody(const Eigen::VectorXf& weights, std::span<const float> body,
                                    bool cleanup, FitScratch& scratch,
                                    Eigen::VectorXf& out) const;

  const ClothingModel& model() const { return model_; }
  const BodyCorrespondence& correspondence() const { return correspondence_; }

 private:
  ClothingFitter(ClothingModel model, BodyCorrespondence correspondence)
      : model_(std::move(model)), correspondence_(std::move(correspondence)) {}

  ClothingModel model_;
  BodyCorrespondence correspondence_;
};

}  // namespace fitbase::clothing

#endif  // FITBASE_CLOTHING_CLOTHING_FITTER_H_
