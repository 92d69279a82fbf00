#include "core/clothing_model.h"

#include <cmath>
#include <random>

#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

using ::testing::HasSubstr;

constexpr int kComponents = 4;
constexpr int kVertices = 50;

ExampleDesign Design() {
  Eigen::VectorXd sigmas(kComponents);
  sigmas << 0.04, 0.02, 0.01, 0.005;
  return *MakeExampleDesign(sigmas, 1.5);
}

// Drapes that respond nonlinearly to the weights, so every model differs from the others.
Eigen::MatrixXd ExampleDrapes(const ExampleDesign& design) {
  std::mt19937_64 rng(7);
  auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * 0x1.0p-53 - 0.5; };
  Eigen::MatrixXd drapes(3 * kVertices, design.example_count());
  for (double& value : drapes.reshaped()) value = uniform();
  return drapes;
}

Eigen::VectorXf Fit(const ClothingModel& model, const Eigen::VectorXd& weights) {
  Eigen::VectorXf features, out;
  FitClothing(model, weights.cast<float>(), features, out);
  return out;
}

TEST(ExampleDesignTest, MeanThenPlusThenMinusExamples) {
  const ExampleDesign design = Design();
  EXPECT_EQ(design.example_count(), 9);
  EXPECT_EQ(design.Label(0), "mean");
  EXPECT_EQ(design.Label(2), "+2");
  EXPECT_EQ(design.Label(6), "-2");
  EXPECT_TRUE(design.Weights(0).isZero());
  EXPECT_DOUBLE_EQ(design.Weights(2)(1), 1.5 * 0.02);
  EXPECT_DOUBLE_EQ(design.Weights(6)(1), -1.5 * 0.02);
  EXPECT_EQ(design.Weights(6).cwiseAbs().sum(), 1.5 * 0.02);
}

TEST(ExampleDesignTest, RejectsBadSigmasAndScale) {
  EXPECT_THAT(MakeExampleDesign(Eigen::VectorXd::Ones(2), 0.0),
              StatusIs(absl::StatusCode::kInvalidArgument, "scale"));
  EXPECT_THAT(MakeExampleDesign(Eigen::VectorXd::Zero(2), 1.0),
              StatusIs(absl::StatusCode::kInvalidArgument, "component 1 has sigma 0"));
  EXPECT_THAT(MakeExampleDesign(Eigen::VectorXd(), 1.0),
              StatusIs(absl::StatusCode::kInvalidArgument, "no components"));
}

TEST(ClothingModelTest, QuadraticReproducesEveryExample) {
  const ExampleDesign design = Design();
  const Eigen::MatrixXd drapes = ExampleDrapes(design);
  const ClothingModel model = *BuildClothingModel(ClothingMethod::kQuadratic, design, drapes);
  EXPECT_EQ(model.term_count(), 2 * kComponents);
  for (int e = 0; e < design.example_count(); ++e) {
    EXPECT_LT((Fit(model, design.Weights(e)).cast<double>() - drapes.col(e)).cwiseAbs().maxCoeff(),
              1e-5)
        << design.Label(e);
  }
}

TEST(ClothingModelTest, LinearReproducesTheMeanAndTheCentralDifference) {
  const ExampleDesign design = Design();
  const Eigen::MatrixXd drapes = ExampleDrapes(design);
  const ClothingModel model = *BuildClothingModel(ClothingMethod::kLinear, design, drapes);
  EXPECT_EQ(model.term_count(), kComponents);
  EXPECT_LT((Fit(model, design.Weights(0)).cast<double>() - drapes.col(0)).cwiseAbs().maxCoeff(),
            1e-6);
  // g(+e) - g(-e) equals the examples' difference; the examples themselves are not reproduced
  // because these drapes are not linear in the weights.
  const Eigen::VectorXd difference =
      (Fit(model, design.Weights(3)) - Fit(model, design.Weights(3 + kComponents))).cast<double>();
  EXPECT_LT((difference - (drapes.col(3) - drapes.col(3 + kComponents))).cwiseAbs().maxCoeff(),
            1e-5);
  EXPECT_GT((Fit(model, design.Weights(3)).cast<double>() - drapes.col(3)).cwiseAbs().maxCoeff(),
            1e-2);
}

// Two components, one vertex: the plus examples are e1 = (0, 0, 0) and e2 = (2, 2, 0). The
// clothing mean is (1, 1, 0); the components are (e_k - mean) / |e_k - mean|, that is
// -(1, 1, 0) / sqrt(2) and (1, 1, 0) / sqrt(2), weighted directly by the avatar weights.
TEST(ClothingModelTest, PaperMatchesAHandComputedCase) {
  Eigen::VectorXd sigmas(2);
  sigmas << 0.1, 0.05;
  const ExampleDesign design = *MakeExampleDesign(sigmas, 1.0);
  Eigen::MatrixXd drapes = Eigen::MatrixXd::Constant(3, 5, 9.0);  // mean and minus unused.
  drapes.col(1) << 0, 0, 0;
  drapes.col(2) << 2, 2, 0;
  const ClothingModel model = *BuildClothingModel(ClothingMethod::kPaper, design, drapes);
  EXPECT_TRUE(model.mean().isApprox(Eigen::Vector3f(1, 1, 0)));
  const float r = std::sqrt(0.5f);
  EXPECT_TRUE(model.terms().col(0).isApprox(Eigen::Vector3f(-r, -r, 0)));
  EXPECT_TRUE(model.terms().col(1).isApprox(Eigen::Vector3f(r, r, 0)));
  Eigen::VectorXd w(2);
  w << 0.3, 0.1;  // 1 + (-0.3 + 0.1) / sqrt(2) on x and y.
  const Eigen::VectorXf fit = Fit(model, w);
  EXPECT_NEAR(fit(0), 1 - 0.2 * r, 1e-6);
  EXPECT_NEAR(fit(1), 1 - 0.2 * r, 1e-6);
  EXPECT_NEAR(fit(2), 0, 1e-6);
}

TEST(ClothingModelTest, BatchEqualsSingleFits) {
  const ExampleDesign design = Design();
  const ClothingModel model =
      *BuildClothingModel(ClothingMethod::kQuadratic, design, ExampleDrapes(design));
  Eigen::MatrixXf weights(kComponents, 3);
  weights << 0.01, -0.02, 0.03, 0.0, 0.005, -0.01, 0.02, 0.01, 0.0, -0.004, 0.002, 0.001;
  Eigen::MatrixXf batch;
  FitClothingBatch(model, weights, batch);
  for (int b = 0; b < 3; ++b) {
    EXPECT_LT((batch.col(b) - Fit(model, weights.col(b).cast<double>())).cwiseAbs().maxCoeff(),
              1e-6);
  }
}

TEST(ClothingModelTest, RejectsExamplesOfTheWrongShape) {
  const ExampleDesign design = Design();
  EXPECT_THAT(BuildClothingModel(ClothingMethod::kLinear, design, Eigen::MatrixXd::Zero(30, 5)),
              StatusIs(absl::StatusCode::kInvalidArgument, "2N + 1 examples for N = 4"));
  Eigen::MatrixXd drapes = ExampleDrapes(design);
  drapes(4, 4) = std::nan("");
  EXPECT_THAT(BuildClothingModel(ClothingMethod::kLinear, design, drapes),
              StatusIs(absl::StatusCode::kInvalidArgument, "not finite"));
}

TEST(ClothingModelTest, ChecksWeightsAndModels) {
  const ExampleDesign design = Design();
  ClothingModel model = *BuildClothingModel(ClothingMethod::kLinear, design, ExampleDrapes(design));
  EXPECT_TRUE(ValidateClothingModel(model).ok());
  EXPECT_THAT(CheckFitWeights(model, Eigen::VectorXf::Zero(3)),
              StatusIs(absl::StatusCode::kInvalidArgument, "got 3 avatar weights"));
  Eigen::VectorXf weights = Eigen::VectorXf::Zero(kComponents);
  weights(1) = std::nanf("");
  EXPECT_THAT(CheckFitWeights(model, weights),
              StatusIs(absl::StatusCode::kInvalidArgument, "not finite"));
  model.term_component[2] = kComponents;
  EXPECT_THAT(ValidateClothingModel(model),
              StatusIs(absl::StatusCode::kInvalidArgument, "uses component 4 of 4"));
}

TEST(ClothingMethodTest, NamesRoundTrip) {
  for (auto method : {ClothingMethod::kPaper, ClothingMethod::kLinear, ClothingMethod::kQuadratic}) {
    EXPECT_EQ(*ParseClothingMethod(ClothingMethodName(method)), method);
  }
  EXPECT_THAT(ParseClothingMethod("cubic"),
              StatusIs(absl::StatusCode::kInvalidArgument, "unknown clothing method 'cubic'"));
}

}  // namespace
}  // namespace fitbase::core
