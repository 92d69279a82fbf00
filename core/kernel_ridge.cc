#include "core/kernel_ridge.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "Eigen/Eigenvalues"
#include "absl/strings/str_cat.h"

namespace fitbase::core {

absl::StatusOr<KernelRidge> FitKernelRidge(const Eigen::MatrixXd& inputs,
                                           const Eigen::MatrixXd& targets,
                                           const KernelRidgeOptions& options) {
  const Eigen::Index m = inputs.cols();
  if (inputs.rows() < 1 || m < 2 || targets.rows() != m || targets.cols() < 1) {
    return absl::InvalidArgumentError(absl::StrCat(
        "kernel ridge needs inputs d x M (M >= 2) and targets M x C; got ", inputs.rows(), " x ",
        m, " and ", targets.rows(), " x ", targets.cols()));
  }
  if (!inputs.allFinite() || !targets.allFinite()) {
    return absl::InvalidArgumentError("kernel ridge inputs or targets are not finite");
  }
  if (options.length_scale_factors.empty() || options.ridges.empty()) {
    return absl::InvalidArgumentError("kernel ridge needs length scales and ridges to try");
  }
  for (double f : options.length_scale_factors) {
    if (!(f > 0) || !std::isfinite(f)) {
      return absl::InvalidArgumentError(absl::StrCat("length scale factor ", f, " is not > 0"));
    }
  }
  for (double r : options.ridges) {
    if (!(r > 0) || !std::isfinite(r)) {
      return absl::InvalidArgumentError(absl::StrCat("ridge ", r, " is not > 0"));
    }
  }
  const Eigen::VectorXd norms = inputs.colwise().squaredNorm().transpose();
  Eigen::MatrixXd squared = (-2.0 * inputs.transpose() * inputs).colwise() + norms;
  squared.rowwise() += norms.transpose();
  squared = squared.cwiseMax(0.0);
  squared.diagonal().setZero();
  std::vector<double> distances;
  distances.reserve(static_cast<size_t>(m * (m - 1) / 2));
  for (Eigen::Index j = 1; j < m; ++j) {
    for (Eigen::Index i = 0; i < j; ++i) distances.push_back(std::sqrt(squared(i, j)));
  }
  const auto middle = distances.begin() + static_cast<std::ptrdiff_t>(distances.size() / 2);
  std::nth_element(distances.begin(), middle, distances.end());
  const double median = *middle;
  if (!(median > 0)) {
    return absl::InvalidArgumentError("kernel ridge inputs are (mostly) all equal");
  }

  KernelRidge best;
  double best_loo = std::numeric_limits<double>::infinity();
  for (double factor : options.length_scale_factors) {
    const double l = factor * median;
    const Eigen::MatrixXd kernel = (squared * (-0.5 / (l * l))).array().exp().matrix();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(kernel);
    const Eigen::MatrixXd& q = eigen.eigenvectors();
    const Eigen::VectorXd values = eigen.eigenvalues().cwiseMax(0.0);
    const Eigen::MatrixXd qty = q.transpose() * targets;
    const Eigen::MatrixXd q_squared = q.array().square().matrix();
    for (double ridge : options.ridges) {
      const Eigen::VectorXd inverse = (values.array() + ridge).inverse().matrix();
      const Eigen::MatrixXd alpha = q * (inverse.asDiagonal() * qty);
      const Eigen::VectorXd hat_diagonal = q_squared * inverse;
      const double loo =
          (alpha.array().colwise() / hat_diagonal.array()).matrix().rowwise().squaredNorm().sum();
      if (loo < best_loo) {
        best_loo = loo;
        best.length_scale = l;
        best.ridge = ridge;
        best.coefficients = alpha.transpose();
      }
    }
  }
  best.centers = inputs;
  best.loo_rms = std::sqrt(best_loo / static_cast<double>(m));
  best.train_rms = std::sqrt(targets.rowwise().squaredNorm().sum() / static_cast<double>(m));
  return best;
}

Eigen::VectorXd PredictKernelRidge(const KernelRidge& model, const Eigen::VectorXd& x) {
  const Eigen::VectorXd k =
      ((model.centers.colwise() - x).colwise().squaredNorm().transpose() *
       (-0.5 / (model.length_scale * model.length_scale)))
          .array()
          .exp()
          .matrix();
  return model.coefficients * k;
}

}  // namespace fitbase::core
