#include "clothing/clothing_model.h"

#include <cmath>
#include <random>

#include "Eigen/QR"
#include "core/random.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::clothing {
namespace {

using core::StatusIs;
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

// A garment whose vertices follow the weights non-linearly: a slide that saturates with
// component 0 (as leggings stop sliding once the waistband grips) and a bulge that grows with
// the square of component 1.
Eigen::MatrixXd SmoothDrape(const ExampleDesign& design, const Eigen::MatrixXd& weights) {
  Eigen::MatrixXd drapes(3 * kVertices, weights.cols());
  for (Eigen::Index b = 0; b < weights.cols(); ++b) {
    const double z0 = weights(0, b) / design.sigmas(0);
    const double z1 = weights(1, b) / design.sigmas(1);
    for (int v = 0; v < kVertices; ++v) {
      drapes(3 * v, b) = 0.01 * v + 0.002 * weights(2, b) / design.sigmas(2);
      drapes(3 * v + 1, b) = 0.02 * std::tanh(z0) * (1 + 0.01 * v);
      drapes(3 * v + 2, b) = 0.005 * z1 * z1 * std::cos(0.1 * v);
    }
  }
  return drapes;
}

Eigen::MatrixXd SampleWeights(const ExampleDesign& design, int count, uint64_t seed) {
  core::Random random(seed, 0);
  Eigen::MatrixXd weights(kComponents, count);
  for (int b = 0; b < count; ++b) {
    for (int k = 0; k < kComponents; ++k) weights(k, b) = random.Normal(0, design.sigmas(k));
  }
  return weights;
}

double RmsError(const ClothingModel& model, const ExampleDesign& design,
                const Eigen::MatrixXd& weights) {
  const Eigen::MatrixXd truth = SmoothDrape(design, weights);
  double squared = 0;
  for (Eigen::Index b = 0; b < weights.cols(); ++b) {
    squared += (Fit(model, weights.col(b)).cast<double>() - truth.col(b)).squaredNorm();
  }
  return std::sqrt(squared / static_cast<double>(weights.cols() * kVertices));
}

// The axis examples' weights: N x (2N + 1), in ExampleDesign order.
Eigen::MatrixXd AxisWeights(const ExampleDesign& design) {
  Eigen::MatrixXd weights(kComponents, design.example_count());
  for (int e = 0; e < design.example_count(); ++e) weights.col(e) = design.Weights(e);
  return weights;
}

// `linear` on SmoothDrape's axis examples.
ClothingModel AxisLinearModel(const ExampleDesign& design) {
  return *BuildClothingModel(ClothingMethod::kLinear, design,
                             SmoothDrape(design, AxisWeights(design)));
}

ClothingModel KernelModel(const ExampleDesign& design, KernelBuildReport* report,
                          int sample_count = 120, const KernelBuildOptions& options = {}) {
  SampledDrapes samples;
  samples.weights = SampleWeights(design, sample_count, 1);
  samples.drapes = SmoothDrape(design, samples.weights);
  absl::StatusOr<ClothingModel> model = BuildKernelClothingModel(
      design, SmoothDrape(design, AxisWeights(design)), samples, options, report);
  EXPECT_TRUE(model.ok()) << model.status();
  return *std::move(model);
}

TEST(KernelClothingModelTest, LearnsWhatTheLinearModelMissesOnNewBodies) {
  const ExampleDesign design = Design();
  KernelBuildReport report;
  const ClothingModel kernel = KernelModel(design, &report);
  EXPECT_TRUE(ValidateClothingModel(kernel).ok());
  const ClothingModel linear = AxisLinearModel(design);
  const Eigen::MatrixXd held_out = SampleWeights(design, 40, 2);
  const double linear_error = RmsError(linear, design, held_out);
  const double kernel_error = RmsError(kernel, design, held_out);
  EXPECT_LT(kernel_error, 0.4 * linear_error) << linear_error << " " << kernel_error;
  // The report's leave-one-out estimate is of the same order as the held-out error.
  EXPECT_GT(report.linear_rms_mm, 1000 * 0.5 * linear_error);
  EXPECT_LT(report.loo_rms_mm, 1000 * 3 * kernel_error + 0.05);
  EXPECT_GE(report.outputs, 1);
  EXPECT_GE(report.kept_energy, 0.999);
  // The misses follow components 0 and 1 only (2 is linear, 3 moves nothing): the relevance
  // search gives the other two a reach far beyond the samples.
  EXPECT_EQ(report.input_scaling, "relevance");
  const Eigen::VectorXf reach =  // In units of sigma.
      kernel.kernel.input_scale.cwiseProduct(design.sigmas.cast<float>()).cwiseInverse();
  EXPECT_GT(reach.tail<2>().minCoeff(), 10 * reach.head<2>().maxCoeff()) << reach.transpose();
  // The mean body is a training body, and the fit there is its drape (the axis model's mean).
  EXPECT_LT((Fit(kernel, Eigen::VectorXd::Zero(kComponents)) - linear.mean()).cwiseAbs().maxCoeff(),
            2e-4);
}

TEST(KernelClothingModelTest, ChoosesTheKernelShapeOfTheLowerLeaveOneOutError) {
  const ExampleDesign design = Design();
  KernelBuildReport gaussian_report, matern_report, chosen_report;
  const ClothingModel gaussian = KernelModel(design, &gaussian_report, 120,
                                             {.shapes = {core::KernelShape::kGaussian}});
  const ClothingModel matern = KernelModel(design, &matern_report, 120,
                                           {.shapes = {core::KernelShape::kMatern32}});
  const ClothingModel chosen = KernelModel(design, &chosen_report);
  EXPECT_EQ(gaussian.kernel.shape, core::KernelShape::kGaussian);
  EXPECT_EQ(matern.kernel.shape, core::KernelShape::kMatern32);
  EXPECT_EQ(gaussian_report.shape, "gaussian");
  EXPECT_EQ(matern_report.shape, "matern32");
  const bool matern_better = matern_report.loo_rms_mm < gaussian_report.loo_rms_mm;
  EXPECT_EQ(chosen.kernel.shape, matern_better ? matern.kernel.shape : gaussian.kernel.shape);
  EXPECT_EQ(chosen_report.loo_rms_mm,
            std::min(matern_report.loo_rms_mm, gaussian_report.loo_rms_mm));
  EXPECT_EQ(chosen.basis, (matern_better ? matern : gaussian).basis);
  EXPECT_TRUE(ValidateClothingModel(matern).ok());
  // Far from every training body a Matern correction falls to 0 too, if more slowly than a
  // Gaussian one (as exp(-r), not exp(-r^2 / 2)).
  Eigen::VectorXd far = 100 * design.sigmas;
  ClothingModel linear = matern;
  linear.method = ClothingMethod::kLinear;
  linear.basis.conservativeResize(Eigen::NoChange, 1 + linear.term_count());
  linear.kernel = {};
  EXPECT_LT((Fit(matern, far) - Fit(linear, far)).cwiseAbs().maxCoeff(), 1e-5);
  const Eigen::MatrixXd held_out = SampleWeights(design, 40, 2);
  EXPECT_LT(RmsError(matern, design, held_out), 0.5 * RmsError(linear, design, held_out));
  EXPECT_THAT(BuildKernelClothingModel(design, ExampleDrapes(design),
                                       {SampleWeights(design, 3, 1),
                                        Eigen::MatrixXd::Zero(3 * kVertices, 3)},
                                       {.shapes = {}}, nullptr),
              StatusIs(absl::StatusCode::kInvalidArgument, "no kernel shape"));
}

TEST(KernelClothingModelTest, SearchesTheShapesSideBySideToTheSameBytes) {
  const ExampleDesign design = Design();
  KernelBuildReport one_report, two_report;
  const ClothingModel one = KernelModel(design, &one_report, 120, {.threads = 1});
  const ClothingModel two = KernelModel(design, &two_report, 120, {.threads = 2});
  // 120 samples are enough for the relevance search, so both shapes were searched.
  EXPECT_EQ(two_report.input_scaling, "relevance");
  EXPECT_EQ(one.basis, two.basis);
  EXPECT_EQ(one.kernel.shape, two.kernel.shape);
  EXPECT_EQ(one.kernel.length_scale, two.kernel.length_scale);
  EXPECT_EQ(one.kernel.input_scale, two.kernel.input_scale);
  EXPECT_EQ(one.kernel.centers, two.kernel.centers);
  EXPECT_EQ(one.kernel.coefficients, two.kernel.coefficients);
  EXPECT_EQ(one_report.loo_rms_mm, two_report.loo_rms_mm);
  // More threads than shapes: one per shape is started, no more.
  EXPECT_EQ(KernelModel(design, nullptr, 120, {.threads = 8}).basis, one.basis);
  EXPECT_THAT(BuildKernelClothingModel(
                  design, ExampleDrapes(design),
                  {SampleWeights(design, 3, 1), Eigen::MatrixXd::Zero(3 * kVertices, 3)},
                  {.threads = 0}, nullptr),
              StatusIs(absl::StatusCode::kInvalidArgument, "at least one thread"));
}

// A search on the first bodies (9 axis examples and 111 of 240 samples) finds the reaches
// the whole set's search finds, to a factor of the search's step, and the model fitted with
// them to all 249 bodies is as close on new bodies; a limit at or above the count changes no
// byte.
TEST(KernelClothingModelTest, SearchesOnTheFirstBodiesAndFitsAllOfThem) {
  const ExampleDesign design = Design();
  KernelBuildReport all_report, first_report, limit_report;
  const ClothingModel all = KernelModel(design, &all_report, 240);
  const ClothingModel first = KernelModel(design, &first_report, 240, {.search_bodies = 120});
  EXPECT_EQ(all_report.searched_bodies, 249);
  EXPECT_EQ(first_report.searched_bodies, 120);
  EXPECT_EQ(first_report.input_scaling, "relevance");
  EXPECT_EQ(first.kernel.center_count(), 249);
  EXPECT_TRUE(ValidateClothingModel(first).ok());
  const Eigen::ArrayXf ratio = first.kernel.input_scale.array() / all.kernel.input_scale.array();
  EXPECT_LE(ratio.head<2>().maxCoeff(), 2.01f) << ratio.transpose();
  EXPECT_GE(ratio.head<2>().minCoeff(), 0.49f) << ratio.transpose();
  const Eigen::MatrixXd held_out = SampleWeights(design, 40, 2);
  const double all_error = RmsError(all, design, held_out);
  EXPECT_LT(RmsError(first, design, held_out), 1.25 * all_error) << all_error;
  // Fitted to all 249 bodies, not to the 120 searched: closer than the model of those alone.
  EXPECT_LT(RmsError(first, design, held_out),
            RmsError(KernelModel(design, nullptr, 111), design, held_out));

  const ClothingModel limit = KernelModel(design, &limit_report, 240, {.search_bodies = 249});
  EXPECT_EQ(limit.basis, all.basis);
  EXPECT_EQ(limit.kernel.coefficients, all.kernel.coefficients);
  EXPECT_EQ(limit_report.loo_rms_mm, all_report.loo_rms_mm);
  EXPECT_THAT(BuildKernelClothingModel(
                  design, ExampleDrapes(design),
                  {SampleWeights(design, 3, 1), Eigen::MatrixXd::Zero(3 * kVertices, 3)},
                  {.search_bodies = 1}, nullptr),
              StatusIs(absl::StatusCode::kInvalidArgument, "at least 2 training bodies"));
}

// The axis examples and the samples of KernelModel, and the least-squares linear model over
// them: (1 + N) x D, the mean first.
Eigen::MatrixXd LeastSquaresLinearPart(const ExampleDesign& design, int sample_count) {
  Eigen::MatrixXd weights(kComponents, design.example_count() + sample_count);
  weights << AxisWeights(design), SampleWeights(design, sample_count, 1);
  Eigen::MatrixXd features(weights.cols(), 1 + kComponents);
  features.col(0).setOnes();
  features.rightCols(kComponents) = weights.transpose();
  return features.colPivHouseholderQr().solve(SmoothDrape(design, weights).transpose());
}

TEST(KernelClothingModelTest, FitsTheLinearPartToEveryTrainingBodyWhenThereAreEnough) {
  const ExampleDesign design = Design();
  // 9 axis examples and 120 samples: at least kLeastSquaresBodiesPerComponent per component.
  KernelBuildReport report;
  const ClothingModel kernel = KernelModel(design, &report);
  EXPECT_EQ(report.linear_part, "least-squares");
  const Eigen::MatrixXd expected = LeastSquaresLinearPart(design, 120).transpose();
  EXPECT_LT(
      (kernel.basis.leftCols(1 + kComponents).cast<double>() - expected).cwiseAbs().maxCoeff(),
      1e-6);
  // Not the axis examples' model: SmoothDrape's bulge (the square of component 1) lifts the
  // mean of the population's drapes above the mean body's drape.
  const ClothingModel axis = AxisLinearModel(design);
  EXPECT_GT((kernel.basis.col(0) - axis.basis.col(0)).cwiseAbs().maxCoeff(), 1e-3);

  // 9 axis examples and 20 samples: too few to fit 1 + N coefficients well; the axis model.
  const ClothingModel few = KernelModel(design, &report, 20);
  EXPECT_EQ(report.linear_part, "axis");
  EXPECT_EQ(few.basis.leftCols(1 + kComponents), axis.basis);
}

TEST(KernelClothingModelTest, KeepsOneLengthScaleWithFewTrainingBodies) {
  const ExampleDesign design = Design();
  KernelBuildReport report;
  // 9 axis examples and 10 samples: fewer than kRelevanceBodiesPerComponent per component.
  static_assert(9 + 10 < kRelevanceBodiesPerComponent * kComponents);
  const ClothingModel kernel = KernelModel(design, &report, 10);
  EXPECT_THAT(report.input_scaling, ::testing::AnyOf("sigma", "response"));
  // And the first shape of the options, the Gaussian, whatever the leave-one-out error says.
  EXPECT_EQ(kernel.kernel.shape, core::KernelShape::kGaussian);
  const ClothingModel matern =
      KernelModel(design, &report, 10, {.shapes = {core::KernelShape::kMatern32}});
  EXPECT_EQ(matern.kernel.shape, core::KernelShape::kMatern32);
  EXPECT_TRUE(ValidateClothingModel(kernel).ok());

  // Many bodies, but the search limited to fewer than kRelevanceBodiesPerComponent per
  // component: the count searched decides (one length scale, the first shape of the options),
  // and the kernel is still fitted to all of them.
  const ClothingModel limited =
      KernelModel(design, &report, 240,
                  {.shapes = {core::KernelShape::kMatern32, core::KernelShape::kGaussian},
                   .search_bodies = 19});
  EXPECT_EQ(report.searched_bodies, 19);
  EXPECT_THAT(report.input_scaling, ::testing::AnyOf("sigma", "response"));
  EXPECT_EQ(limited.kernel.shape, core::KernelShape::kMatern32);
  EXPECT_EQ(limited.kernel.center_count(), 249);
  EXPECT_TRUE(ValidateClothingModel(limited).ok());
}

TEST(KernelClothingModelTest, FallsBackToTheLinearModelFarFromEveryTrainingBody) {
  const ExampleDesign design = Design();
  const ClothingModel kernel = KernelModel(design, nullptr);
  ClothingModel linear = kernel;
  linear.method = ClothingMethod::kLinear;
  linear.basis.conservativeResize(Eigen::NoChange, 1 + linear.term_count());
  linear.kernel = {};
  Eigen::VectorXd far = 40 * design.sigmas;
  EXPECT_LT((Fit(kernel, far) - Fit(linear, far)).cwiseAbs().maxCoeff(), 1e-5);
}

TEST(KernelClothingModelTest, BatchEqualsSingleFits) {
  const ExampleDesign design = Design();
  const ClothingModel model = KernelModel(design, nullptr);
  const Eigen::MatrixXf weights = SampleWeights(design, 3, 9).cast<float>();
  Eigen::MatrixXf batch;
  FitClothingBatch(model, weights, batch);
  for (int b = 0; b < 3; ++b) {
    EXPECT_LT((batch.col(b) - Fit(model, weights.col(b).cast<double>())).cwiseAbs().maxCoeff(),
              1e-6);
  }
}

TEST(KernelClothingModelTest, ChecksItsInputsAndItsCorrection) {
  const ExampleDesign design = Design();
  const Eigen::MatrixXd drapes = ExampleDrapes(design);
  SampledDrapes samples;
  samples.weights = Eigen::MatrixXd::Zero(kComponents, 2);
  samples.drapes = Eigen::MatrixXd::Zero(3 * kVertices, 3);
  EXPECT_THAT(BuildKernelClothingModel(design, drapes, samples, {}, nullptr),
              StatusIs(absl::StatusCode::kInvalidArgument, "sampled drapes are"));
  EXPECT_THAT(BuildClothingModel(ClothingMethod::kKernel, design, drapes),
              StatusIs(absl::StatusCode::kInvalidArgument, "BuildKernelClothingModel"));
  ClothingModel model = KernelModel(design, nullptr);
  model.kernel.centers.conservativeResize(Eigen::NoChange, model.kernel.center_count() - 1);
  EXPECT_THAT(ValidateClothingModel(model),
              StatusIs(absl::StatusCode::kInvalidArgument, "kernel correction has"));
  model = KernelModel(design, nullptr);
  model.kernel.length_scale = 0;
  EXPECT_THAT(ValidateClothingModel(model),
              StatusIs(absl::StatusCode::kInvalidArgument, "length scale"));
  model = KernelModel(design, nullptr);
  model.method = ClothingMethod::kLinear;
  EXPECT_THAT(ValidateClothingModel(model),
              StatusIs(absl::StatusCode::kInvalidArgument, "has no kernel correction"));
}

TEST(ClothingMethodTest, NamesRoundTrip) {
  for (auto method : {ClothingMethod::kPaper, ClothingMethod::kLinear, ClothingMethod::kQuadratic,
                      ClothingMethod::kKernel}) {
    EXPECT_EQ(*ParseClothingMethod(ClothingMethodName(method)), method);
  }
  EXPECT_THAT(ParseClothingMethod("cubic"),
              StatusIs(absl::StatusCode::kInvalidArgument, "unknown clothing method 'cubic'"));
}

}  // namespace
}  // namespace fitbase::clothing
