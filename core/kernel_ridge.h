#ifndef FITBASE_CORE_KERNEL_RIDGE_H_
#define FITBASE_CORE_KERNEL_RIDGE_H_

#include <vector>

#include "Eigen/Core"
#include "absl/status/statusor.h"

namespace fitbase::core {

// Gaussian-kernel ridge regression, k(a, b) = exp(-|a - b|^2 / (2 l^2)):
//   y(x) = sum_j coefficients.col(j) * k(x, centers.col(j)).
// Far from every center the prediction falls to zero, so a correction learned this way leaves
// the model it corrects alone where it has seen no data.
struct KernelRidge {
  double length_scale = 1.0;      // l, in the inputs' unit.
  double ridge = 0.0;             // lambda, relative to k(x, x) = 1.
  Eigen::MatrixXd centers;        // d x M: the training inputs.
  Eigen::MatrixXd coefficients;   // C x M.
  double loo_rms = 0.0;           // Leave-one-out error: RMS over the M points of |y - y_-i|.
  double train_rms = 0.0;         // RMS over the M points of |y|: what predicting 0 would miss.
};

struct KernelRidgeOptions {
  // Candidates for l, as multiples of the median distance between two training inputs.
  std::vector<double> length_scale_factors = {0.25, 0.35, 0.5, 0.7, 1.0, 1.4, 2.0};
  std::vector<double> ridges = {1e-4, 1e-3, 1e-2, 1e-1, 1.0};
};

// inputs: d x M (d >= 1, M >= 2), targets: M x C (C >= 1), all finite. Chooses l and lambda
// from the grid by the exact leave-one-out error (the hat matrix of ridge regression: the
// residual without point i is alpha_i / (G^-1)_ii, G = K + lambda I), then solves for the
// coefficients. Deterministic. InvalidArgument for bad shapes, non-finite values, an empty
// grid or all inputs equal.
absl::StatusOr<KernelRidge> FitKernelRidge(const Eigen::MatrixXd& inputs,
                                           const Eigen::MatrixXd& targets,
                                           const KernelRidgeOptions& options = {});

// The prediction at x (d): C values.
Eigen::VectorXd PredictKernelRidge(const KernelRidge& model, const Eigen::VectorXd& x);

}  // namespace fitbase::core

#endif  // FITBASE_CORE_KERNEL_RIDGE_H_
