#include "clothing/clothing_fitter.h"

#include "core/status_macros.h"

namespace fitbase::clothing {
namespace {

template <typename Matrix>
size_t BytesOf(const Matrix& m) {
  return sizeof(typename Matrix::Scalar) * static_cast<size_t>(m.size());
}

template <typename T>
size_t BytesOf(const std::vector<T>& v) {
  return sizeof(T) * v.size();
}

}  // namespace

ClothingFitter::ClothingFitter(ClothingModel model, BodyCorrespondence correspondence)
    : model_(std::move(model)), correspondence_(std::move(correspondence)) {
  mean_ = model_.basis.col(0);
  columns_ = core::QuantizeColumns(model_.basis.rightCols(model_.basis.cols() - 1));
  model_.basis.resize(0, 0);
}

absl::StatusOr<ClothingFitter> ClothingFitter::Create(ClothingModel model,
                                                      BodyCorrespondence correspondence) {
  RETURN_IF_ERROR(ValidateClothingModel(model));
  RETURN_IF_ERROR(ValidateBodyCorrespondence(correspondence, model.vertex_count(),
                                             model.component_count));
  return ClothingFitter(std::move(model), std::move(correspondence));
}

size_t ClothingFitter::bytes() const {
  const KernelCorrection& kernel = model_.kernel;
  const BodyCorrespondence& c = correspondence_;
  return BytesOf(mean_) + columns_.bytes() + BytesOf(kernel.centers) +
         BytesOf(kernel.coefficients) + BytesOf(kernel.input_scale) + BytesOf(c.body_vertices) +
         BytesOf(c.body_mean) + BytesOf(c.body_components) + BytesOf(c.corners) +
         BytesOf(c.barycentric) + BytesOf(c.guard_body) + BytesOf(c.guard_triangles) +
         BytesOf(c.body_triangles) + BytesOf(c.neighbor_offsets) + BytesOf(c.neighbors);
}

void ClothingFitter::Evaluate(const Eigen::VectorXf& weights, FitScratch& scratch,
                              Eigen::VectorXf& out) const {
  Eigen::VectorXf& features = scratch.features;
  ClothingFeatures(model_, weights, features);
  // The mean's coefficient is 1: it is added exactly, as the float product added it.
  out = mean_;
  core::MultiplyAccumulate(columns_, features.tail(features.size() - 1), out);
}

absl::StatusOr<int64_t> ClothingFitter::Fit(const Eigen::VectorXf& weights, bool cleanup,
                                            FitScratch& scratch, Eigen::VectorXf& out) const {
  RETURN_IF_ERROR(CheckFitWeights(model_, weights));
  Evaluate(weights, scratch, out);
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
  Evaluate(weights, scratch, out);
  BodyPointsOfWeights(correspondence_, weights, c.body);
  FollowBody(correspondence_, c.body, c.own_body, c, out.data());
  if (!cleanup) return 0;
  return PushOutOfBodyPoints(correspondence_, c.own_body, c.anchor_rows, c, out.data());
}

}  // namespace fitbase::clothing
