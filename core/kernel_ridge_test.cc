#include "core/kernel_ridge.h"

#include <cmath>

#include "core/random.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

// y = sin(x0) + 0.5 x1^2, a smooth non-linear function, sampled at M points in [-2, 2]^2.
void Sample(int m, uint64_t seed, Eigen::MatrixXd& inputs, Eigen::MatrixXd& targets) {
  Random random(seed, 0);
  inputs.resize(2, m);
  targets.resize(m, 1);
  for (int i = 0; i < m; ++i) {
    inputs(0, i) = random.Uniform(-2, 2);
    inputs(1, i) = random.Uniform(-2, 2);
    targets(i, 0) = std::sin(inputs(0, i)) + 0.5 * inputs(1, i) * inputs(1, i);
  }
}

KernelRidge Fitted(const Eigen::MatrixXd& inputs, const Eigen::MatrixXd& targets,
                   const KernelRidgeOptions& options = {}) {
  absl::StatusOr<KernelRidge> model = FitKernelRidge(inputs, targets, options);
  EXPECT_TRUE(model.ok()) << model.status();
  return model.ok() ? *std::move(model) : KernelRidge{};
}

TEST(KernelRidgeTest, LearnsASmoothFunctionAndPredictsHeldOutPoints) {
  Eigen::MatrixXd inputs, targets, test_inputs, test_targets;
  Sample(200, 1, inputs, targets);
  Sample(50, 2, test_inputs, test_targets);
  const KernelRidge model = Fitted(inputs, targets);
  double squared = 0;
  for (int i = 0; i < 50; ++i) {
    squared += std::pow(PredictKernelRidge(model, test_inputs.col(i))(0) - test_targets(i, 0), 2);
  }
  const double rms = std::sqrt(squared / 50);
  EXPECT_LT(rms, 0.05 * model.train_rms);
  // Leave-one-out is an honest estimate of the held-out error: the same order.
  EXPECT_LT(model.loo_rms, 3 * rms + 0.01);
  EXPECT_GT(model.loo_rms, rms / 3);
}

TEST(KernelRidgeTest, FallsToZeroFarFromTheData) {
  Eigen::MatrixXd inputs, targets;
  Sample(100, 3, inputs, targets);
  const KernelRidge model = Fitted(inputs, targets);
  EXPECT_NEAR(PredictKernelRidge(model, Eigen::Vector2d(50, 50))(0), 0.0, 1e-9);
}

TEST(KernelRidgeTest, PicksTheLengthScaleByLeaveOneOut) {
  Eigen::MatrixXd inputs, targets;
  Sample(150, 4, inputs, targets);
  KernelRidgeOptions narrow_only;
  narrow_only.length_scale_factors = {0.01};
  const KernelRidge narrow = Fitted(inputs, targets, narrow_only);
  const KernelRidge chosen = Fitted(inputs, targets);
  // A kernel far narrower than the points' spacing cannot predict a left-out point.
  EXPECT_GT(narrow.loo_rms, 0.9 * narrow.train_rms);
  EXPECT_LT(chosen.loo_rms, 0.2 * narrow.loo_rms);
}

TEST(KernelRidgeTest, RelevanceSearchIgnoresAnInputTheTargetsDoNotFollow) {
  // y = sin(2 x0): x1 is noise the isotropic kernel must measure distances in.
  Random random(6, 0);
  Eigen::MatrixXd inputs(2, 120), targets(120, 1);
  for (int i = 0; i < 120; ++i) {
    inputs(0, i) = random.Uniform(-2, 2);
    inputs(1, i) = random.Uniform(-2, 2);
    targets(i, 0) = std::sin(2 * inputs(0, i));
  }
  const KernelRidge isotropic = Fitted(inputs, targets);
  absl::StatusOr<RelevanceFit> relevance = FitKernelRidgeRelevance(
      inputs, targets, Eigen::Vector2d::Constant(1 / isotropic.length_scale));
  ASSERT_TRUE(relevance.ok()) << relevance.status();
  EXPECT_LT(relevance->scales(1), relevance->scales(0) / 4) << relevance->scales.transpose();
  EXPECT_LT(relevance->model.loo_rms, 0.5 * isotropic.loo_rms);
  // The model predicts on the scaled inputs, with l = 1.
  const Eigen::Vector2d x(0.3, -1.1);
  EXPECT_NEAR(PredictKernelRidge(relevance->model, relevance->scales.cwiseProduct(x))(0),
              std::sin(0.6), 0.05);
  absl::StatusOr<RelevanceFit> again = FitKernelRidgeRelevance(
      inputs, targets, Eigen::Vector2d::Constant(1 / isotropic.length_scale));
  EXPECT_TRUE(again->scales == relevance->scales);
  EXPECT_TRUE(again->model.coefficients == relevance->model.coefficients);
  EXPECT_THAT(FitKernelRidgeRelevance(inputs, targets, Eigen::Vector2d(1, 0)),
              StatusIs(absl::StatusCode::kInvalidArgument, "scales > 0"));
  EXPECT_THAT(FitKernelRidgeRelevance(inputs, targets, Eigen::Vector3d(1, 1, 1)),
              StatusIs(absl::StatusCode::kInvalidArgument, "2 finite scales"));
}

TEST(KernelRidgeTest, ShapesAreOneAtZeroAndFallWithDistance) {
  for (const KernelShape shape : {KernelShape::kGaussian, KernelShape::kMatern32}) {
    EXPECT_EQ(KernelOfScaledSquared(shape, 0.0), 1.0);
    EXPECT_GT(KernelOfScaledSquared(shape, 1.0), KernelOfScaledSquared(shape, 2.0));
    EXPECT_LT(KernelOfScaledSquared(shape, 400.0), 1e-6);
    EXPECT_NEAR(KernelOfScaledSquared(shape, 2.0f), KernelOfScaledSquared(shape, 2.0), 1e-7);
  }
  EXPECT_DOUBLE_EQ(KernelOfScaledSquared(KernelShape::kGaussian, 1.0), std::exp(-0.5));
  EXPECT_DOUBLE_EQ(KernelOfScaledSquared(KernelShape::kMatern32, 1.0),
                   (1 + std::sqrt(3.0)) * std::exp(-std::sqrt(3.0)));
  EXPECT_STREQ(KernelShapeName(KernelShape::kMatern32), "matern32");
}

// y = |x0| + 0.3 x1 kinks along x0 = 0, as a drape does where a contact starts. The Gaussian,
// smooth to every order, rounds the kink off; the Matern 3/2 kernel, once differentiable, keeps
// it, and the leave-one-out error says so.
TEST(KernelRidgeTest, TheMaternKernelFollowsAKinkTheGaussianRoundsOff) {
  Random random(8, 0);
  const auto sample = [&](int m, Eigen::MatrixXd& inputs, Eigen::MatrixXd& targets) {
    inputs.resize(2, m);
    targets.resize(m, 1);
    for (int i = 0; i < m; ++i) {
      inputs(0, i) = random.Uniform(-2, 2);
      inputs(1, i) = random.Uniform(-2, 2);
      targets(i, 0) = std::abs(inputs(0, i)) + 0.3 * inputs(1, i);
    }
  };
  Eigen::MatrixXd inputs, targets, test_inputs, test_targets;
  sample(150, inputs, targets);
  sample(200, test_inputs, test_targets);
  const KernelRidge gaussian = Fitted(inputs, targets);
  const KernelRidge matern = Fitted(inputs, targets, {.shape = KernelShape::kMatern32});
  EXPECT_EQ(gaussian.shape, KernelShape::kGaussian);
  EXPECT_EQ(matern.shape, KernelShape::kMatern32);
  const auto held_out_rms = [&](const KernelRidge& model) {
    double squared = 0;
    for (int i = 0; i < test_inputs.cols(); ++i) {
      squared += std::pow(PredictKernelRidge(model, test_inputs.col(i))(0) - test_targets(i, 0), 2);
    }
    return std::sqrt(squared / static_cast<double>(test_inputs.cols()));
  };
  EXPECT_LT(matern.loo_rms, 0.8 * gaussian.loo_rms) << matern.loo_rms << " " << gaussian.loo_rms;
  EXPECT_LT(held_out_rms(matern), 0.9 * held_out_rms(gaussian));
  absl::StatusOr<RelevanceFit> relevance =
      FitKernelRidgeRelevance(inputs, targets, Eigen::Vector2d::Constant(1 / matern.length_scale),
                              {.shape = KernelShape::kMatern32});
  ASSERT_TRUE(relevance.ok()) << relevance.status();
  EXPECT_EQ(relevance->model.shape, KernelShape::kMatern32);
  EXPECT_LE(relevance->model.loo_rms, matern.loo_rms);
}

TEST(KernelRidgeTest, IsDeterministic) {
  Eigen::MatrixXd inputs, targets;
  Sample(80, 5, inputs, targets);
  const KernelRidge a = Fitted(inputs, targets);
  const KernelRidge b = Fitted(inputs, targets);
  EXPECT_EQ(a.length_scale, b.length_scale);
  EXPECT_EQ(a.ridge, b.ridge);
  EXPECT_TRUE(a.coefficients == b.coefficients);
}

TEST(KernelRidgeTest, RejectsBadInput) {
  const Eigen::MatrixXd inputs = Eigen::MatrixXd::Random(2, 10);
  EXPECT_THAT(FitKernelRidge(inputs, Eigen::MatrixXd::Zero(9, 1)),
              StatusIs(absl::StatusCode::kInvalidArgument, "targets M x C"));
  Eigen::MatrixXd bad = inputs;
  bad(0, 3) = std::nan("");
  EXPECT_THAT(FitKernelRidge(bad, Eigen::MatrixXd::Zero(10, 1)),
              StatusIs(absl::StatusCode::kInvalidArgument, "not finite"));
  EXPECT_THAT(FitKernelRidge(Eigen::MatrixXd::Ones(2, 10), Eigen::MatrixXd::Zero(10, 1)),
              StatusIs(absl::StatusCode::kInvalidArgument, "all equal"));
  KernelRidgeOptions options;
  options.ridges = {0.0};
  EXPECT_THAT(FitKernelRidge(inputs, Eigen::MatrixXd::Zero(10, 1), options),
              StatusIs(absl::StatusCode::kInvalidArgument, "ridge 0"));
}

}  // namespace
}  // namespace fitbase::core
