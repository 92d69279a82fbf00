#include "core/pca_basis.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include "Eigen/QR"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

using ::testing::HasSubstr;

constexpr int kVertexCount = 500;
constexpr int kDim = 3 * kVertexCount;
constexpr int kSampleCount = 60;
constexpr int kTrueRank = 5;
constexpr double kTrueScales[kTrueRank] = {0.05, 0.03, 0.02, 0.01, 0.005};  // Meters.

// Uniform in [-1, 1) from the raw 64-bit stream, so values do not depend on the standard
// library's distribution implementations.
double Uniform(std::mt19937_64& rng) {
  return 2.0 * static_cast<double>(rng() >> 11) * 0x1.0p-53 - 1.0;
}

Eigen::MatrixXd UniformMatrix(std::mt19937_64& rng, int rows, int cols) {
  Eigen::MatrixXd m(rows, cols);
  for (double& value : m.reshaped()) value = Uniform(rng);
  return m;
}

// Samples mean + sum_j scale_j * w_j * direction_j + noise, with orthonormal directions and
// unit-variance uniform weights; the noise fills the remaining K-1-5 modes with tiny variance.
struct LowRankModel {
  Eigen::VectorXd mean;
  Eigen::MatrixXd directions;  // kDim x kTrueRank.
};

LowRankModel MakeModel(std::mt19937_64& rng) {
  LowRankModel model;
  model.mean = UniformMatrix(rng, kDim, 1);
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(UniformMatrix(rng, kDim, kTrueRank));
  model.directions = qr.householderQ() * Eigen::MatrixXd::Identity(kDim, kTrueRank);
  return model;
}

Eigen::MatrixXd SampleModel(const LowRankModel& model, std::mt19937_64& rng, int count,
                            double noise) {
  const Eigen::Map<const Eigen::VectorXd> scales(kTrueScales, kTrueRank);
  const Eigen::MatrixXd weights = std::sqrt(3.0) * UniformMatrix(rng, kTrueRank, count);
  return (model.directions * scales.asDiagonal() * weights).colwise() + model.mean +
         noise * UniformMatrix(rng, kDim, count);
}

Eigen::MatrixXd TrainingSamples(double noise = 1e-6) {
  std::mt19937_64 rng(42);
  const LowRankModel model = MakeModel(rng);
  return SampleModel(model, rng, kSampleCount, noise);
}

ComponentSelection Count(int count) {
  return {.rule = ComponentSelection::Rule::kCount, .count = count};
}

ComponentSelection Fraction(double fraction) {
  return {.rule = ComponentSelection::Rule::kVarianceFraction, .variance_fraction = fraction};
}

ComponentSelection MaxMeanError(double target_mm) {
  return {.rule = ComponentSelection::Rule::kMaxMeanErrorMm, .max_mean_error_mm = target_mm};
}

PcaBasis BuildOrDie(const Eigen::MatrixXd& samples, const ComponentSelection& selection) {
  absl::StatusOr<PcaBasis> basis = BuildPcaBasis(samples, selection);
  EXPECT_TRUE(basis.ok()) << basis.status();
  return *std::move(basis);
}

TEST(PcaBasisTest, KeepsAllNonNullModesOrthonormal) {
  // The noise modes are ~1e-10 of the leading variance, where the Gram route alone loses
  // orthogonality; every one of them must still come out orthonormal.
  const PcaBasis basis = BuildOrDie(TrainingSamples(), Count(kSampleCount - 1));
  ASSERT_EQ(basis.components.cols(), kSampleCount - 1);
  ASSERT_EQ(basis.components.rows(), kDim);
  const Eigen::MatrixXd gram = basis.components.transpose() * basis.components;
  EXPECT_LT((gram - Eigen::MatrixXd::Identity(kSampleCount - 1, kSampleCount - 1)).norm(), 1e-9);
}

TEST(PcaBasisTest, VariancesDescendPositiveAndMatchTheData) {
  const Eigen::MatrixXd samples = TrainingSamples();
  const PcaBasis basis = BuildOrDie(samples, Count(kSampleCount - 1));
  EXPECT_EQ(basis.sample_count, kSampleCount);
  EXPECT_TRUE(basis.mean.isApprox(samples.rowwise().mean(), 1e-14));
  for (int k = 0; k < basis.variances.size(); ++k) {
    EXPECT_GT(basis.variances(k), 0.0) << k;
    if (k > 0) {
      EXPECT_LE(basis.variances(k), basis.variances(k - 1)) << k;
    }
  }
  const Eigen::MatrixXd centered = samples.colwise() - basis.mean;
  const double total = centered.squaredNorm() / (kSampleCount - 1);
  EXPECT_NEAR(basis.total_variance, total, 1e-12 * total);
  EXPECT_LE(basis.explained_variance_ratio.sum(), 1.0 + 1e-12);
  EXPECT_NEAR(basis.explained_variance_ratio.sum(), 1.0, 1e-9);  // All non-null modes kept.
  EXPECT_TRUE(basis.explained_variance_ratio.isApprox(basis.variances / basis.total_variance));
  // Each variance is the sample variance of that component's weights.
  const Eigen::MatrixXd weights = basis.components.transpose() * centered;
  for (int k = 0; k < kTrueRank; ++k) {
    const double variance = weights.row(k).squaredNorm() / (kSampleCount - 1);
    EXPECT_NEAR(variance, basis.variances(k), 1e-9 * basis.variances(k)) << k;
  }
  // The leading modes recover the model's scales (uniform weights have unit variance).
  EXPECT_NEAR(std::sqrt(basis.variances(0)), kTrueScales[0], 0.3 * kTrueScales[0]);
  EXPECT_LT(basis.variances(kTrueRank), 1e-6 * basis.variances(kTrueRank - 1));
}

TEST(PcaBasisTest, TrainingErrorMatchesProjectAndReconstruct) {
  const Eigen::MatrixXd samples = TrainingSamples();
  const PcaBasis basis = BuildOrDie(samples, Count(3));
  double mean_sum = 0.0;
  double max_mm = 0.0;
  for (int k = 0; k < kSampleCount; ++k) {
    const Eigen::VectorXd weights = ProjectOntoBasis(basis, samples.col(k));
    ASSERT_EQ(weights.size(), 3);
    const ReconstructionError error =
        MeasureReconstructionError(samples.col(k), ReconstructFromWeights(basis, weights));
    mean_sum += error.mean_mm;
    max_mm = std::max(max_mm, error.max_mm);
  }
  // Every sample has the same vertex count, so the mean of the means is the overall mean.
  EXPECT_NEAR(mean_sum / kSampleCount, basis.training_error.mean_mm,
              1e-9 * basis.training_error.mean_mm);
  EXPECT_NEAR(max_mm, basis.training_error.max_mm, 1e-9 * max_mm);
  EXPECT_GT(basis.training_error.mean_mm, 0.1);  // Two real modes are missing.
}

TEST(PcaBasisTest, SampleInTheSpanReconstructsExactly) {
  std::mt19937_64 rng(7);
  const LowRankModel model = MakeModel(rng);
  const PcaBasis basis =
      BuildOrDie(SampleModel(model, rng, kSampleCount, /*noise=*/0.0), Count(kTrueRank));
  EXPECT_LT(basis.training_error.max_mm, 1e-9);
  const Eigen::VectorXd unseen = SampleModel(model, rng, 1, /*noise=*/0.0);
  const ReconstructionError error = MeasureReconstructionError(
      unseen, ReconstructFromWeights(basis, ProjectOntoBasis(basis, unseen)));
  EXPECT_LT(error.max_mm, 1e-9);
  // Noise-free rank-5 data has exactly five non-null modes.
  const absl::StatusOr<PcaBasis> too_many =
      BuildPcaBasis(SampleModel(model, rng, kSampleCount, 0.0), Count(kTrueRank + 1));
  ASSERT_EQ(too_many.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(too_many.status().message(), HasSubstr("6"));
  EXPECT_THAT(too_many.status().message(), HasSubstr("5"));
}

TEST(PcaBasisTest, CountKeepsExactlyThatMany) {
  const PcaBasis basis = BuildOrDie(TrainingSamples(), Count(3));
  EXPECT_EQ(basis.components.cols(), 3);
  EXPECT_EQ(basis.variances.size(), 3);
  EXPECT_EQ(basis.explained_variance_ratio.size(), 3);
}

TEST(PcaBasisTest, VarianceFractionPicksTheFewestComponents) {
  const Eigen::MatrixXd samples = TrainingSamples();
  const PcaBasis full = BuildOrDie(samples, Count(kSampleCount - 1));
  std::vector<double> cumulative(full.explained_variance_ratio.size());
  std::partial_sum(full.explained_variance_ratio.begin(), full.explained_variance_ratio.end(),
                   cumulative.begin());
  // Halfway between the shares of 3 and 4 components needs 4; exactly the share of 3 needs 3.
  const double between = 0.5 * (cumulative[2] + cumulative[3]);
  EXPECT_EQ(BuildOrDie(samples, Fraction(between)).components.cols(), 4);
  EXPECT_EQ(BuildOrDie(samples, Fraction(cumulative[2])).components.cols(), 3);
  EXPECT_EQ(BuildOrDie(samples, Fraction(1e-6)).components.cols(), 1);
  EXPECT_EQ(BuildOrDie(samples, Fraction(1.0)).components.cols(), kSampleCount - 1);
}

TEST(PcaBasisTest, MaxMeanErrorPicksTheFewestComponents) {
  const Eigen::MatrixXd samples = TrainingSamples();
  std::vector<double> error_mm;  // error_mm[n - 1]: mean training error with n components.
  for (int n = 1; n <= 6; ++n) {
    error_mm.push_back(BuildOrDie(samples, Count(n)).training_error.mean_mm);
  }
  const PcaBasis between = BuildOrDie(samples, MaxMeanError(0.5 * (error_mm[2] + error_mm[3])));
  EXPECT_EQ(between.components.cols(), 4);

  // The default target of 1 mm: N components meet it and N - 1 do not.
  const PcaBasis basis = BuildOrDie(samples, ComponentSelection{});
  const int n = static_cast<int>(basis.components.cols());
  ASSERT_GE(n, 2);
  EXPECT_LE(basis.training_error.mean_mm, 1.0);
  EXPECT_GT(BuildOrDie(samples, Count(n - 1)).training_error.mean_mm, 1.0);
  EXPECT_NEAR(basis.training_error.mean_mm, error_mm[n - 1], 1e-9 * error_mm[n - 1]);
}

TEST(PcaBasisTest, MaxMeanErrorKeepsAtLeastOneComponent) {
  const PcaBasis basis = BuildOrDie(TrainingSamples(), MaxMeanError(1e6));
  EXPECT_EQ(basis.components.cols(), 1);
}

TEST(PcaBasisTest, RejectsBadSamples) {
  const Eigen::MatrixXd samples = TrainingSamples();
  EXPECT_EQ(BuildPcaBasis(samples.leftCols(1), {}).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(BuildPcaBasis(Eigen::MatrixXd(kDim, 0), {}).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(BuildPcaBasis(samples.topRows(kDim - 1), {}).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(BuildPcaBasis(Eigen::MatrixXd(0, 4), {}).status().code(),
            absl::StatusCode::kInvalidArgument);

  Eigen::MatrixXd with_nan = samples;
  with_nan(10, 3) = std::numeric_limits<double>::quiet_NaN();
  const absl::Status nan_status = BuildPcaBasis(with_nan, {}).status();
  EXPECT_EQ(nan_status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(nan_status.message(), HasSubstr("sample 3 has a non-finite value"));
  Eigen::MatrixXd with_inf = samples;
  with_inf(0, 0) = std::numeric_limits<double>::infinity();
  EXPECT_THAT(BuildPcaBasis(with_inf, {}).status().message(), HasSubstr("sample 0"));

  // Three copies do not average back exactly, so the centered data is rounding noise, not 0.
  const absl::Status identical = BuildPcaBasis(samples.col(0).replicate(1, 3), {}).status();
  EXPECT_EQ(identical.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(identical.message(), HasSubstr("no variance"));
}

TEST(PcaBasisTest, RejectsBadSelections) {
  const Eigen::MatrixXd samples = TrainingSamples();
  const absl::Status too_many = BuildPcaBasis(samples, Count(kSampleCount)).status();
  EXPECT_EQ(too_many.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(too_many.message(), HasSubstr("60"));
  EXPECT_THAT(too_many.message(), HasSubstr("59"));
  EXPECT_EQ(BuildPcaBasis(samples, Count(0)).status().code(), absl::StatusCode::kInvalidArgument);
  for (double fraction : {0.0, -0.5, 1.0 + 1e-9, std::numeric_limits<double>::quiet_NaN()}) {
    EXPECT_EQ(BuildPcaBasis(samples, Fraction(fraction)).status().code(),
              absl::StatusCode::kInvalidArgument)
        << fraction;
  }
  for (double target : {0.0, -1.0, std::numeric_limits<double>::infinity()}) {
    EXPECT_EQ(BuildPcaBasis(samples, MaxMeanError(target)).status().code(),
              absl::StatusCode::kInvalidArgument)
        << target;
  }
}

TEST(PcaBasisTest, IsDeterministic) {
  const Eigen::MatrixXd samples = TrainingSamples();
  const PcaBasis first = BuildOrDie(samples, Count(kSampleCount - 1));
  const PcaBasis second = BuildOrDie(samples, Count(kSampleCount - 1));
  EXPECT_TRUE(first.components == second.components);
  EXPECT_TRUE(first.variances == second.variances);
  EXPECT_TRUE(first.mean == second.mean);
}

TEST(PcaBasisTest, SignsFollowTheLargestEntry) {
  const Eigen::MatrixXd samples = TrainingSamples();
  const PcaBasis basis = BuildOrDie(samples, Count(kSampleCount - 1));
  for (int j = 0; j < basis.components.cols(); ++j) {
    Eigen::Index largest = 0;
    basis.components.col(j).cwiseAbs().maxCoeff(&largest);
    EXPECT_GT(basis.components(largest, j), 0.0) << j;
  }
  // Reordering and negating the data changes the eigensolver's signs but not the result.
  std::vector<int> order(kSampleCount);
  std::iota(order.begin(), order.end(), 0);
  std::reverse(order.begin(), order.end());
  const Eigen::MatrixXd reflected =
      (-samples(Eigen::all, order)).colwise() + 2.0 * samples.rowwise().mean();
  const PcaBasis other = BuildOrDie(reflected, Count(kTrueRank));
  for (int j = 0; j < kTrueRank; ++j) {
    EXPECT_LT((other.components.col(j) - basis.components.col(j)).norm(), 1e-6) << j;
  }
}

TEST(PcaBasisTest, ExampleFromComponentStepsAlongOneComponent) {
  const PcaBasis basis = BuildOrDie(TrainingSamples(), Count(4));
  const Eigen::VectorXd example = ExampleFromComponent(basis, 2, -3.0);
  Eigen::VectorXd expected_weights = Eigen::VectorXd::Zero(4);
  expected_weights(2) = -3.0 * std::sqrt(basis.variances(2));
  EXPECT_LT((ProjectOntoBasis(basis, example) - expected_weights).norm(), 1e-12);
  // Fewer weights than components use the leading components only.
  EXPECT_LT((ReconstructFromWeights(basis, expected_weights.head(3)) - example).norm(), 1e-12);
}

TEST(PcaBasisTest, MeasuresPerVertexDistanceInMillimeters) {
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(6);
  Eigen::VectorXd moved = x;
  moved.head(3) << 0.003, 0.0, -0.004;  // First vertex moves 5 mm, second stays.
  const ReconstructionError error = MeasureReconstructionError(x, moved);
  EXPECT_NEAR(error.mean_mm, 2.5, 1e-12);
  EXPECT_NEAR(error.max_mm, 5.0, 1e-12);
}

}  // namespace
}  // namespace fitbase::core
