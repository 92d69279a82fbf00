#ifndef FITBASE_CORE_PCA_BASIS_H_
#define FITBASE_CORE_PCA_BASIS_H_

#include "Eigen/Core"
#include "absl/status/statusor.h"

namespace fitbase::core {

// How many principal components to keep.
struct ComponentSelection {
  enum class Rule {
    kMaxMeanErrorMm,    // Fewest components (>= 1) with mean per-vertex training error <= target.
    kCount,             // Exactly `count` components, at most the non-null modes (<= K-1).
    kVarianceFraction,  // Fewest components explaining >= `variance_fraction` of the variance.
  };
  Rule rule = Rule::kMaxMeanErrorMm;
  double max_mean_error_mm = 1.0;
  int count = 0;
  double variance_fraction = 0.0;
};

// Per-vertex Euclidean reconstruction error, millimeters.
struct ReconstructionError {
  double mean_mm = 0.0;
  double max_mm = 0.0;
};

// A linear shape space x ~ mean + components * weights over flattened meshes.
// Flattened layout: D = 3V values, vertex-major and xyz-interleaved (x0 y0 z0 x1 ...), meters.
struct PcaBasis {
  Eigen::VectorXd mean;                      // D.
  Eigen::MatrixXd components;                // D x N, orthonormal columns, variance descending.
  Eigen::VectorXd variances;                 // N, sample variance of each weight, m^2 (sigma_k^2).
  Eigen::VectorXd explained_variance_ratio;  // N, share of the total variance.
  double total_variance = 0.0;               // Sum of all K-1 sample variances, m^2.
  ReconstructionError training_error;        // Over the training samples with N components.
  int sample_count = 0;                      // K.
};

// PCA of K samples (columns of `samples`, D x K, K >= 2, finite). Uses the K x K Gram matrix,
// never a D x D covariance. Modes with variance below 1e-12 of the largest are numerically
// null and never kept. Component signs are fixed (largest-magnitude entry positive) so the
// result does not depend on the eigensolver's sign choice. InvalidArgument for bad samples,
// samples without variance, or a selection that is out of range.
absl::StatusOr<PcaBasis> BuildPcaBasis(const Eigen::MatrixXd& samples,
                                       const ComponentSelection& selection);

// weights = components^T (x - mean); x: D, returns N.
Eigen::VectorXd ProjectOntoBasis(const PcaBasis& basis, const Eigen::VectorXd& x);

// mean + components * weights; weights: N (fewer uses the leading ones), returns D.
Eigen::VectorXd ReconstructFromWeights(const PcaBasis& basis, const Eigen::VectorXd& weights);

// Per-vertex distance between two flattened meshes of the same size D = 3V, in mm.
ReconstructionError MeasureReconstructionError(const Eigen::VectorXd& x,
                                               const Eigen::VectorXd& reconstructed);

// The example avatar mean + sigma * sqrt(variances[k]) * components.col(k); k in [0, N).
Eigen::VectorXd ExampleFromComponent(const PcaBasis& basis, int k, double sigma);

}  // namespace fitbase::core

#endif  // FITBASE_CORE_PCA_BASIS_H_
