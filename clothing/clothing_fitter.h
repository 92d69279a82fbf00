#ifndef FITBASE_CLOTHING_CLOTHING_FITTER_H_
#define FITBASE_CLOTHING_CLOTHING_FITTER_H_

#include <cstddef>
#include <cstdint>
#include <span>

#include "Eigen/Core"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "clothing/body_correspondence.h"
#include "clothing/clothing_model.h"
#include "core/matrix_vector.h"

namespace fitbase::clothing {

// Per-thread working memory of ClothingFitter::Fit, so a fit allocates nothing once warm.
struct FitScratch {
  Eigen::VectorXf features;
  CleanupScratch cleanup;
};

// The online fit of one garment size: the clothing model evaluated at a customer's avatar
// weights, then (optionally) the collision clean-up. Immutable after Create, so one fitter
// serves any number of threads, each with its own FitScratch.
//
// The fitter holds the model's basis as the mean in floats and its other columns in 16 bits
// (core::Int16Columns): half the bytes to hold and to stream once per fit. On
// male_casualsuit01 M (8.4k vertices) the basis takes 3.2 MB instead of 6.4, the fitter 6.2
// instead of 9.4 (the correspondence stays in floats), and the product 60 us instead of 80.
// Each entry is within 1/65534 of its column's largest magnitude, micrometres of the fitted
// garment (docs/fit-accuracy.md, "Sixteen bits per entry").
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

  int component_count() const { return model_.component_count; }
  int64_t vertex_count() const { return mean_.size() / 3; }
  const BodyCorrespondence& correspondence() const { return correspondence_; }
  // What the fitter holds in memory, bytes: its basis, the kernel's training bodies and
  // coefficients, and the correspondence's arrays. A cache of fitters is bounded by this.
  size_t bytes() const;

 private:
  ClothingFitter(ClothingModel model, BodyCorrespondence correspondence);

  // The model's product, out (3V) = mean + columns * features[1:]; out is resized only when
  // its size differs.
  void Evaluate(const Eigen::VectorXf& weights, FitScratch& scratch, Eigen::VectorXf& out) const;

  // The model's terms and kernel, which give a fit's features; its basis is held below, and
  // empty here.
  ClothingModel model_;
  Eigen::VectorXf mean_;        // 3V floats, m.
  core::Int16Columns columns_;  // 3V x (T + C).
  BodyCorrespondence correspondence_;
};

}  // namespace fitbase::clothing

#endif  // FITBASE_CLOTHING_CLOTHING_FITTER_H_
