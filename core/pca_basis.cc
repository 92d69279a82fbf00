#include "core/pca_basis.h"

#include <algorithm>
#include <cmath>

#include "Eigen/Eigenvalues"
#include "Eigen/QR"
#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/status_macros.h"

namespace fitbase::core {
namespace {

constexpr double kMmPerMeter = 1000.0;
// Eigenvalues of the Gram matrix carry an absolute error near eps * lambda_max, so modes below
// this relative size are rounding noise (centering alone always leaves one such mode).
constexpr double kNullModeRelativeTolerance = 1e-12;
// Centering rounds each entry by about eps * |x|, so (near-)identical samples still show modes
// of that size; spread below this share of the samples' norm counts as no variance at all.
constexpr double kCenteringNoiseTolerance = 1e-12;

// The non-null eigenpairs of the centered Gram matrix, eigenvalues descending.
struct Modes {
  Eigen::VectorXd values;
  Eigen::MatrixXd vectors;  // K x M.
  double total = 0.0;       // Trace of the Gram matrix: the sum of all eigenvalues.
};

absl::Status ValidateSamples(const Eigen::MatrixXd& samples) {
  if (samples.cols() < 2) {
    return absl::InvalidArgumentError(
        absl::StrCat("PCA needs at least 2 samples, got ", samples.cols()));
  }
  if (samples.rows() == 0 || samples.rows() % 3 != 0) {
    return absl::InvalidArgumentError(absl::StrCat(
        "sample size ", samples.rows(), " is not a positive multiple of 3 (x, y, z per vertex)"));
  }
  for (Eigen::Index k = 0; k < samples.cols(); ++k) {
    if (!samples.col(k).allFinite()) {
      return absl::InvalidArgumentError(absl::StrCat("sample ", k, " has a non-finite value"));
    }
  }
  return absl::OkStatus();
}

// Rejects selections that are invalid whatever the data; the count is checked against the
// available modes later.
absl::Status ValidateSelection(const ComponentSelection& selection) {
  using Rule = ComponentSelection::Rule;
  switch (selection.rule) {
    case Rule::kMaxMeanErrorMm:
      if (!(selection.max_mean_error_mm > 0.0) || !std::isfinite(selection.max_mean_error_mm)) {
        return absl::InvalidArgumentError(absl::StrCat(
            "max_mean_error_mm must be positive and finite, got ", selection.max_mean_error_mm));
      }
      return absl::OkStatus();
    case Rule::kCount:
      if (selection.count < 1) {
        return absl::InvalidArgumentError(
            absl::StrCat("component count must be at least 1, got ", selection.count));
      }
      return absl::OkStatus();
    case Rule::kVarianceFraction:
      if (!(selection.variance_fraction > 0.0 && selection.variance_fraction <= 1.0)) {
        return absl::InvalidArgumentError(
            absl::StrCat("variance_fraction must be in (0, 1], got ", selection.variance_fraction));
      }
      return absl::OkStatus();
  }
  return absl::InvalidArgumentError("unknown component selection rule");
}

absl::StatusOr<Modes> ComputeModes(const Eigen::MatrixXd& centered, double samples_norm) {
  const Eigen::Index k = centered.cols();
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(k, k);
  gram.selfadjointView<Eigen::Lower>().rankUpdate(centered.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(gram);
  if (solver.info() != Eigen::Success) {
    return absl::InternalError("the Gram matrix eigensolver did not converge");
  }
  // The solver sorts ascending; PCA wants the largest modes first.
  const Eigen::VectorXd values = solver.eigenvalues().reverse();
  const double noise_norm = kCenteringNoiseTolerance * samples_norm;
  const double cutoff = std::max(kNullModeRelativeTolerance * values(0), noise_norm * noise_norm);
  const Eigen::Index available = (values.array() > cutoff).count();
  if (available == 0) {
    return absl::InvalidArgumentError(
        "the samples have no variance (all identical up to rounding)");
  }
  return Modes{values.head(available),
               solver.eigenvectors().rowwise().reverse().leftCols(available), gram.trace()};
}

// The Euclidean length of every vertex (xyz triple) of every column of `flat`, lazily, so a
// reduction over it needs no V*K temporary.
auto VertexNorms(const Eigen::MatrixXd& flat) {
  return flat.reshaped(3, flat.size() / 3).colwise().norm();
}

// Mean and max over all vertices of all columns of `residual` (meters), in mm.
ReconstructionError PerVertexError(const Eigen::MatrixXd& residual) {
  const Eigen::RowVectorXd distances = VertexNorms(residual);
  return {kMmPerMeter * distances.mean(), kMmPerMeter * distances.maxCoeff()};
}

// With orthonormal Gram eigenvectors V, the first n components reconstruct Xc V_n V_n^T, so
// the residual loses the rank-1 term (Xc v_n) v_n^T per step: O(DK) each, which lets the
// search stop at the first count meeting the target instead of refitting every candidate.
int CountForMeanError(const Eigen::MatrixXd& centered, const Modes& modes, double target_mm) {
  const int available = static_cast<int>(modes.values.size());
  Eigen::MatrixXd residual = centered;
  for (int n = 1; n < available; ++n) {
    const auto v = modes.vectors.col(n - 1);
    residual.noalias() -= (centered * v) * v.transpose();
    if (kMmPerMeter * VertexNorms(residual).mean() <= target_mm) return n;
  }
  return available;
}

absl::StatusOr<int> SelectCount(const ComponentSelection& selection,
                                const Eigen::MatrixXd& centered, const Modes& modes) {
  const int available = static_cast<int>(modes.values.size());
  switch (selection.rule) {
    case ComponentSelection::Rule::kMaxMeanErrorMm:
      return CountForMeanError(centered, modes, selection.max_mean_error_mm);
    case ComponentSelection::Rule::kCount:
      if (selection.count > available) {
        return absl::InvalidArgumentError(absl::StrCat("component count ", selection.count,
                                                       " exceeds the ", available,
                                                       " non-null modes of the samples"));
      }
      return selection.count;
    case ComponentSelection::Rule::kVarianceFraction: {
      double cumulative = 0.0;
      for (int n = 1; n <= available; ++n) {
        cumulative += modes.values(n - 1) / modes.total;
        if (cumulative >= selection.variance_fraction) return n;
      }
      // Without the null modes, and with rounding, the ratios can sum to just under 1.
      return available;
    }
  }
  return absl::InvalidArgumentError("unknown component selection rule");
}

// Components Xc v / sqrt(lambda) lose orthogonality roughly as eps * lambda_max / lambda, so
// the smallest kept modes are re-orthonormalized; QR keeps the column order, hence the
// leading (accurate) directions, and the sign is then fixed by the largest-magnitude entry.
Eigen::MatrixXd OrthonormalComponents(const Eigen::MatrixXd& centered, const Modes& modes,
                                      int count) {
  const Eigen::MatrixXd raw =
      centered * (modes.vectors.leftCols(count) *
                  modes.values.head(count).cwiseSqrt().cwiseInverse().asDiagonal());
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(raw);
  Eigen::MatrixXd components = qr.householderQ() * Eigen::MatrixXd::Identity(raw.rows(), count);
  for (int j = 0; j < count; ++j) {
    Eigen::Index largest = 0;
    components.col(j).cwiseAbs().maxCoeff(&largest);
    if (components(largest, j) < 0.0) components.col(j) *= -1.0;
  }
  return components;
}

}  // namespace

absl::StatusOr<PcaBasis> BuildPcaBasis(const Eigen::MatrixXd& samples,
                                       const ComponentSelection& selection) {
  RETURN_IF_ERROR(ValidateSamples(samples));
  RETURN_IF_ERROR(ValidateSelection(selection));
  const Eigen::Index k = samples.cols();
  PcaBasis basis;
  basis.mean = samples.rowwise().mean();
  const Eigen::MatrixXd centered = samples.colwise() - basis.mean;
  ASSIGN_OR_RETURN(const Modes modes, ComputeModes(centered, samples.norm()));
  ASSIGN_OR_RETURN(const int count, SelectCount(selection, centered, modes));

  basis.components = OrthonormalComponents(centered, modes, count);
  basis.variances = modes.values.head(count) / static_cast<double>(k - 1);
  basis.explained_variance_ratio = modes.values.head(count) / modes.total;
  basis.total_variance = modes.total / static_cast<double>(k - 1);
  const Eigen::MatrixXd weights = basis.components.transpose() * centered;
  basis.training_error = PerVertexError(centered - basis.components * weights);
  basis.sample_count = static_cast<int>(k);
  return basis;
}

Eigen::VectorXd ProjectOntoBasis(const PcaBasis& basis, const Eigen::VectorXd& x) {
  return basis.components.transpose() * (x - basis.mean);
}

Eigen::VectorXd ReconstructFromWeights(const PcaBasis& basis, const Eigen::VectorXd& weights) {
  return basis.mean + basis.components.leftCols(weights.size()) * weights;
}

ReconstructionError MeasureReconstructionError(const Eigen::VectorXd& x,
                                               const Eigen::VectorXd& reconstructed) {
  return PerVertexError(x - reconstructed);
}

Eigen::VectorXd ExampleFromComponent(const PcaBasis& basis, int k, double sigma) {
  return basis.mean + (sigma * std::sqrt(basis.variances(k))) * basis.components.col(k);
}

}  // namespace fitbase::core
