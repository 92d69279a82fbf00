#ifndef FITBASE_CORE_KERNEL_RIDGE_H_
#define FITBASE_CORE_KERNEL_RIDGE_H_

#include <cmath>
#include <cstdint>
#include <iterator>
#include <vector>

#include "Eigen/Core"
#include "absl/status/statusor.h"

namespace fitbase::core {

// The kernel's profile, as a function of q = |a - b|^2 / l^2 (stored in clothing bases: the
// numbers never change meaning).
enum class KernelShape : int32_t {
  kGaussian = 0,  // exp(-q / 2): infinitely smooth.
  // (1 + r) exp(-r), r = sqrt(3 q): the Matern kernel of smoothness 3/2, once differentiable.
  // It follows a function that kinks, which a Gaussian, smooth to every order, rounds off
  // unless it has many centres near the kink.
  kMatern32 = 1,
};

template <typename T>
T KernelOfScaledSquared(KernelShape shape, T q) {
  if (shape == KernelShape::kMatern32) {
    const T r = std::sqrt(T(3) * q);
    return (T(1) + r) * std::exp(-r);
  }
  return std::exp(T(-0.5) * q);
}

const char* KernelShapeName(KernelShape shape);  // "gaussian", "matern32".

// Kernel ridge regression with a radial kernel k(a, b) = K(|a - b|^2 / l^2) of some shape:
//   y(x) = sum_j coefficients.col(j) * k(x, centers.col(j)).
// Far from every center the prediction falls to zero, so a correction learned this way leaves
// the model it corrects alone where it has seen no data.
struct KernelRidge {
  KernelShape shape = KernelShape::kGaussian;
  double length_scale = 1.0;      // l, in the inputs' unit.
  double ridge = 0.0;             // lambda, relative to k(x, x) = 1.
  Eigen::MatrixXd centers;        // d x M: the training inputs.
  Eigen::MatrixXd coefficients;   // C x M.
  double loo_rms = 0.0;           // Leave-one-out error: RMS over the M points of |y - y_-i|.
  double train_rms = 0.0;         // RMS over the M points of |y|: what predicting 0 would miss.
};

// The ridges the leave-one-out error chooses from, relative to k(x, x) = 1.
inline constexpr double kRidgeGrid[] = {1e-4, 1e-3, 1e-2, 1e-1, 1.0};

struct KernelRidgeOptions {
  KernelShape shape = KernelShape::kGaussian;
  // Candidates for l, as multiples of the median distance between two training inputs.
  std::vector<double> length_scale_factors = {0.25, 0.35, 0.5, 0.7, 1.0, 1.4, 2.0};
  std::vector<double> ridges{std::begin(kRidgeGrid), std::end(kRidgeGrid)};
};

// inputs: d x M (d >= 1, M >= 2), targets: M x C (C >= 1), all finite. Chooses l and lambda
// from the grid by the exact leave-one-out error (the hat matrix of ridge regression: the
// residual without point i is alpha_i / (G^-1)_ii, G = K + lambda I), then solves for the
// coefficients. Deterministic. InvalidArgument for bad shapes, non-finite values, an empty
// grid or all inputs equal.
absl::StatusOr<KernelRidge> FitKernelRidge(const Eigen::MatrixXd& inputs,
                                           const Eigen::MatrixXd& targets,
                                           const KernelRidgeOptions& options = {});

// A relevance search improves the leave-one-out error by at least this share per move, so that
// it stops where moves only trade rounding.
inline constexpr double kRelevanceGain = 1e-3;

struct RelevanceOptions {
  KernelShape shape = KernelShape::kGaussian;
  std::vector<double> ridges{std::begin(kRidgeGrid), std::end(kRidgeGrid)};
  int sweeps = 4;      // Passes over the inputs; the search stops early when one moves none.
  double step = 2.0;   // Factor of one move of a scale.
  int max_steps = 4;   // Moves of one scale in one direction per pass.
};

struct RelevanceFit {
  KernelRidge model;       // On the scaled inputs, l = 1: centers = diag(scales) * inputs.
  Eigen::VectorXd scales;  // d: 1 / the reach of each input (automatic relevance determination).
};

// One scale per input dimension, z = scales .* x, chosen by coordinate search from
// initial_scales (d, > 0; e.g. a FitKernelRidge scaling divided by its length scale) on the
// exact leave-one-out error, with the best ridge of the grid at each step: the inputs the
// targets follow get a short reach and the others a long one, where one length scale for all
// must compromise. Each step costs one eigendecomposition of the M x M kernel. Deterministic.
// InvalidArgument as FitKernelRidge, for scales of the wrong size or not > 0, or bad options.
absl::StatusOr<RelevanceFit> FitKernelRidgeRelevance(const Eigen::MatrixXd& inputs,
                                                    const Eigen::MatrixXd& targets,
                                                    const Eigen::VectorXd& initial_scales,
                                                    const RelevanceOptions& options = {});

// The prediction at x (d): C values.
Eigen::VectorXd PredictKernelRidge(const KernelRidge& model, const Eigen::VectorXd& x);

}  // namespace fitbase::core

#endif  // FITBASE_CORE_KERNEL_RIDGE_H_
