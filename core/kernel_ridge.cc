#include "core/kernel_ridge.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "Eigen/Eigenvalues"
#include "absl/strings/str_cat.h"
#include "core/status_macros.h"

namespace fitbase::core {

namespace {

// M x M squared distances between the columns of inputs (d x M), exact zeros on the diagonal.
Eigen::MatrixXd SquaredDistances(const Eigen::MatrixXd& inputs) {
  const Eigen::VectorXd norms = inputs.colwise().squaredNorm().transpose();
  Eigen::MatrixXd squared = (-2.0 * inputs.transpose() * inputs).colwise() + norms;
  squared.rowwise() += norms.transpose();
  squared = squared.cwiseMax(0.0);
  squared.diagonal().setZero();
  return squared;
}

// The best ridge of the grid for one length scale, by the exact leave-one-out error (sum over
// the M points of |y - y_-i|^2), and the coefficients (C x M) it gives.
struct LengthFit {
  double loo = std::numeric_limits<double>::infinity();
  double ridge = 0;
  Eigen::MatrixXd coefficients;
};

LengthFit FitLength(KernelShape shape, const Eigen::MatrixXd& squared, double l,
                    const Eigen::MatrixXd& targets, const std::vector<double>& ridges) {
  // The Gaussian keeps the arithmetic it had before there were shapes, so its models are the
  // same bytes as before.
  const Eigen::MatrixXd kernel =
      shape == KernelShape::kGaussian
          ? Eigen::MatrixXd((squared * (-0.5 / (l * l))).array().exp().matrix())
          : Eigen::MatrixXd((squared / (l * l)).unaryExpr([shape](double q) {
              return KernelOfScaledSquared(shape, q);
            }));
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(kernel);
  const Eigen::MatrixXd& q = eigen.eigenvectors();
  const Eigen::VectorXd values = eigen.eigenvalues().cwiseMax(0.0);
  const Eigen::MatrixXd qty = q.transpose() * targets;
  const Eigen::MatrixXd q_squared = q.array().square().matrix();
  LengthFit best;
  for (double ridge : ridges) {
    const Eigen::VectorXd inverse = (values.array() + ridge).inverse().matrix();
    const Eigen::MatrixXd alpha = q * (inverse.asDiagonal() * qty);
    const Eigen::VectorXd hat_diagonal = q_squared * inverse;
    const double loo =
        (alpha.array().colwise() / hat_diagonal.array()).matrix().rowwise().squaredNorm().sum();
    if (loo < best.loo) {
      best.loo = loo;
      best.ridge = ridge;
      best.coefficients = alpha.transpose();
    }
  }
  return best;
}

absl::Status CheckShapes(const Eigen::MatrixXd& inputs, const Eigen::MatrixXd& targets,
                         const std::vector<double>& ridges) {
  const Eigen::Index m = inputs.cols();
  if (inputs.rows() < 1 || m < 2 || targets.rows() != m || targets.cols() < 1) {
    return absl::InvalidArgumentError(absl::StrCat(
        "kernel ridge needs inputs d x M (M >= 2) and targets M x C; got ", inputs.rows(), " x ",
        m, " and ", targets.rows(), " x ", targets.cols()));
  }
  if (!inputs.allFinite() || !targets.allFinite()) {
    return absl::InvalidArgumentError("kernel ridge inputs or targets are not finite");
  }
  if (ridges.empty()) return absl::InvalidArgumentError("kernel ridge needs ridges to try");
  for (double r : ridges) {
    if (!(r > 0) || !std::isfinite(r)) {
      return absl::InvalidArgumentError(absl::StrCat("ridge ", r, " is not > 0"));
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<KernelRidge> FitKernelRidge(const Eigen::MatrixXd& inputs,
                                           const Eigen::MatrixXd& targets,
                                           const KernelRidgeOptions& options) {
  RETURN_IF_ERROR(CheckShapes(inputs, targets, options.ridges));
  const Eigen::Index m = inputs.cols();
  if (options.length_scale_factors.empty()) {
    return absl::InvalidArgumentError("kernel ridge needs length scales to try");
  }
  for (double f : options.length_scale_factors) {
    if (!(f > 0) || !std::isfinite(f)) {
      return absl::InvalidArgumentError(absl::StrCat("length scale factor ", f, " is not > 0"));
    }
  }
  const Eigen::MatrixXd squared = SquaredDistances(inputs);
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
    const LengthFit fit = FitLength(options.shape, squared, l, targets, options.ridges);
    if (fit.loo < best_loo) {
      best_loo = fit.loo;
      best.length_scale = l;
      best.ridge = fit.ridge;
      best.coefficients = fit.coefficients;
    }
  }
  best.shape = options.shape;
  best.centers = inputs;
  best.loo_rms = std::sqrt(best_loo / static_cast<double>(m));
  best.train_rms = std::sqrt(targets.rowwise().squaredNorm().sum() / static_cast<double>(m));
  return best;
}

absl::StatusOr<RelevanceFit> FitKernelRidgeRelevance(const Eigen::MatrixXd& inputs,
                                                    const Eigen::MatrixXd& targets,
                                                    const Eigen::VectorXd& initial_scales,
                                                    const RelevanceOptions& options) {
  RETURN_IF_ERROR(CheckShapes(inputs, targets, options.ridges));
  if (initial_scales.size() != inputs.rows() || !initial_scales.allFinite() ||
      (initial_scales.array() <= 0).any()) {
    return absl::InvalidArgumentError(absl::StrCat("relevance search needs ", inputs.rows(),
                                                   " finite scales > 0 to start from"));
  }
  if (options.sweeps < 0 || !(options.step > 1) || !std::isfinite(options.step) ||
      options.max_steps < 1) {
    return absl::InvalidArgumentError(
        "relevance search needs sweeps >= 0, a step > 1 and max steps >= 1");
  }
  const auto evaluate = [&](const Eigen::VectorXd& scales) {
    return FitLength(options.shape, SquaredDistances(scales.asDiagonal() * inputs), 1.0, targets,
                     options.ridges);
  };
  Eigen::VectorXd scales = initial_scales;
  LengthFit best = evaluate(scales);
  // Coordinate search in log scale: each input's scale moves by `step` while the error falls,
  // up (the body measure matters more, at a shorter reach) or down (it matters less).
  for (int sweep = 0; sweep < options.sweeps; ++sweep) {
    bool moved = false;
    for (Eigen::Index k = 0; k < scales.size(); ++k) {
      for (const double factor : {options.step, 1 / options.step}) {
        bool improved = false;
        for (int s = 0; s < options.max_steps; ++s) {
          Eigen::VectorXd trial = scales;
          trial(k) *= factor;
          LengthFit fit = evaluate(trial);
          if (!(fit.loo < best.loo * (1 - kRelevanceGain))) break;
          scales = trial;
          best = std::move(fit);
          improved = true;
        }
        if (improved) {
          moved = true;
          break;  // Not back the way it came.
        }
      }
    }
    if (!moved) break;
  }
  RelevanceFit result;
  result.scales = scales;
  result.model.shape = options.shape;
  result.model.length_scale = 1.0;
  result.model.ridge = best.ridge;
  result.model.coefficients = best.coefficients;
  result.model.centers = scales.asDiagonal() * inputs;
  result.model.loo_rms = std::sqrt(best.loo / static_cast<double>(inputs.cols()));
  result.model.train_rms =
      std::sqrt(targets.rowwise().squaredNorm().sum() / static_cast<double>(inputs.cols()));
  return result;
}

const char* KernelShapeName(KernelShape shape) {
  switch (shape) {
    case KernelShape::kGaussian:
      return "gaussian";
    case KernelShape::kMatern32:
      return "matern32";
  }
  return "unknown";
}

Eigen::VectorXd PredictKernelRidge(const KernelRidge& model, const Eigen::VectorXd& x) {
  const Eigen::VectorXd q = (model.centers.colwise() - x).colwise().squaredNorm().transpose() /
                            (model.length_scale * model.length_scale);
  const KernelShape shape = model.shape;
  return model.coefficients *
         q.unaryExpr([shape](double value) { return KernelOfScaledSquared(shape, value); });
}

}  // namespace fitbase::core
