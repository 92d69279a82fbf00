#include "clothing/clothing_fitter.h"

#include <cmath>
#include <limits>
#include <vector>

#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::clothing {
namespace {

using core::StatusIs;

// One garment vertex 1 mm above the plane y = 0 of a single body triangle; component 0 lifts
// the body, component 1 moves the garment vertex along y.
struct OneVertex {
  ClothingModel model;
  BodyCorrespondence correspondence;
};

OneVertex MakeOneVertex() {
  OneVertex s;
  s.model.method = ClothingMethod::kLinear;
  s.model.component_count = 2;
  s.model.basis = Eigen::MatrixXf::Zero(3, 2);
  s.model.basis.col(0) << 0.2f, 0.001f, 0.2f;
  s.model.basis(1, 1) = 1;
  s.model.term_component = {1};
  s.model.term_power = {1};
  s.correspondence.offset = 0.0025;
  s.correspondence.body_vertices = {0, 1, 2};
  s.correspondence.body_mean.resize(9);
  s.correspondence.body_mean << 0, 0, 0, 0, 0, 1, 1, 0, 0;  // Normal +y.
  s.correspondence.body_components = Eigen::MatrixXf::Zero(9, 2);
  for (int i = 0; i < 3; ++i) s.correspondence.body_components(3 * i + 1, 0) = 1;
  s.correspondence.corners.resize(1, 3);
  s.correspondence.corners << 0, 1, 2;
  s.correspondence.barycentric.resize(1, 3);
  s.correspondence.barycentric << 0.6f, 0.2f, 0.2f;
  return s;
}

TEST(ClothingFitterTest, FitsThenCleansUp) {
  OneVertex s = MakeOneVertex();
  const ClothingFitter fitter = *ClothingFitter::Create(s.model, s.correspondence);
  FitScratch scratch;
  Eigen::VectorXf out;
  const Eigen::VectorXf weights = Eigen::Vector2f(0.0f, 0.01f);  // Garment up by 1 cm.
  EXPECT_EQ(*fitter.Fit(weights, true, scratch, out), 0);
  EXPECT_NEAR(out(1), 0.011f, 1e-7);
  const Eigen::VectorXf lifted = Eigen::Vector2f(0.05f, 0.0f);  // Body up by 5 cm.
  EXPECT_EQ(*fitter.Fit(lifted, false, scratch, out), 0);
  EXPECT_NEAR(out(1), 0.001f, 1e-7);
  EXPECT_EQ(*fitter.Fit(lifted, true, scratch, out), 1);
  EXPECT_NEAR(out(1), 0.0525f, 1e-6);
}

// The fitter's basis in 16 bits: the mean exact, each other column within half a step of its
// scale (1/65534 of its largest magnitude) times its coefficient, and about half the bytes.
TEST(ClothingFitterTest, FitsWithinTheSixteenBitStepOfTheFloatModel) {
  OneVertex s = MakeOneVertex();
  const Eigen::Index rows = 3 * 500;
  s.model.basis = Eigen::MatrixXf::Random(rows, 3) * 0.02f;
  s.model.basis.col(0) = Eigen::VectorXf::Random(rows);
  s.model.term_component = {1, 0};
  s.model.term_power = {1, 2};
  // One anchor per vertex, the same for each (replicated from copies: replicate aliases).
  const auto corners = s.correspondence.corners;
  const auto barycentric = s.correspondence.barycentric;
  s.correspondence.corners = corners.replicate(500, 1);
  s.correspondence.barycentric = barycentric.replicate(500, 1);
  const ClothingFitter fitter = *ClothingFitter::Create(s.model, s.correspondence);
  EXPECT_EQ(fitter.vertex_count(), 500);
  EXPECT_EQ(fitter.component_count(), 2);
  const Eigen::VectorXf weights = Eigen::Vector2f(1.5f, -2.0f);
  FitScratch scratch;
  Eigen::VectorXf out;
  ASSERT_TRUE(fitter.Fit(weights, false, scratch, out).ok());
  Eigen::VectorXf features;
  Eigen::VectorXf exact;
  FitClothing(s.model, weights, features, exact);
  ASSERT_EQ(features.size(), 3);
  double bound = 0;
  for (Eigen::Index k = 1; k < 3; ++k) {
    bound += 0.5 * std::abs(features(k)) * s.model.basis.col(k).cwiseAbs().maxCoeff() / 32767;
  }
  const double error = (out - exact).cwiseAbs().maxCoeff();
  EXPECT_LE(error, bound + 1e-6);
  EXPECT_GT(error, 0);
  // Two more terms hold two bytes per entry and a float scale each.
  s.model.basis.conservativeResize(rows, 5);
  s.model.basis.rightCols(2).setConstant(0.01f);
  s.model.term_component = {1, 0, 1, 0};
  s.model.term_power = {1, 2, 2, 1};
  const ClothingFitter larger = *ClothingFitter::Create(s.model, s.correspondence);
  EXPECT_EQ(larger.bytes() - fitter.bytes(), 2 * (2 * rows + 4));
}

TEST(ClothingFitterTest, RejectsMismatchedPartsAndWeights) {
  OneVertex s = MakeOneVertex();
  s.correspondence.body_components = Eigen::MatrixXf::Zero(9, 3);
  EXPECT_THAT(ClothingFitter::Create(s.model, s.correspondence),
              StatusIs(absl::StatusCode::kInvalidArgument, "expected 2"));
  s = MakeOneVertex();
  const ClothingFitter fitter = *ClothingFitter::Create(s.model, s.correspondence);
  FitScratch scratch;
  Eigen::VectorXf out;
  EXPECT_THAT(fitter.Fit(Eigen::VectorXf::Zero(5), true, scratch, out),
              StatusIs(absl::StatusCode::kInvalidArgument, "got 5 avatar weights"));
}

// The single body triangle of MakeOneVertex as a 3-vertex avatar mesh (3B floats), moved by
// (dx, dy, 0).
std::vector<float> Triangle(float dx, float dy) {
  return {dx, dy, 0, dx, dy, 1, 1 + dx, dy, 0};
}

TEST(ClothingFitterTest, FitToBodyFollowsTheMeshAlongItsNormalOnly) {
  OneVertex s = MakeOneVertex();
  const ClothingFitter fitter = *ClothingFitter::Create(s.model, s.correspondence);
  FitScratch scratch;
  Eigen::VectorXf fitted;
  Eigen::VectorXf out;
  const Eigen::VectorXf weights = Eigen::Vector2f(0.0f, 0.01f);  // 11 mm above y = 0.
  ASSERT_TRUE(fitter.Fit(weights, true, scratch, fitted).ok());
  // The mesh is the body of the weights: the same garment.
  ASSERT_TRUE(fitter.FitToBody(weights, Triangle(0, 0), true, scratch, out).ok());
  EXPECT_EQ(out, fitted);
  // 4 mm out along the normal and 1 cm along the skin: only the 4 mm are carried.
  ASSERT_TRUE(fitter.FitToBody(weights, Triangle(0.01f, 0.004f), true, scratch, out).ok());
  EXPECT_NEAR(out(0), fitted(0), 1e-7);
  EXPECT_NEAR(out(1), 0.015f, 1e-6);
  EXPECT_NEAR(out(2), fitted(2), 1e-7);
}

TEST(ClothingFitterTest, FitToBodyClearsTheMeshNotTheBodyOfTheWeights) {
  OneVertex s = MakeOneVertex();
  const ClothingFitter fitter = *ClothingFitter::Create(s.model, s.correspondence);
  FitScratch scratch;
  Eigen::VectorXf out;
  // 0.5 mm above the body of the weights, inside the 2.5 mm offset.
  const Eigen::VectorXf weights = Eigen::Vector2f(0.0f, -0.0005f);
  // The mesh 1 cm lower: the garment follows it down and is pushed out to 2.5 mm above it,
  // still 7.5 mm under the body of the weights.
  EXPECT_EQ(*fitter.FitToBody(weights, Triangle(0, -0.01f), true, scratch, out), 1);
  EXPECT_NEAR(out(1), -0.0075f, 1e-6);
  EXPECT_EQ(*fitter.FitToBody(weights, Triangle(0, -0.01f), false, scratch, out), 0);
  EXPECT_NEAR(out(1), -0.0095f, 1e-6);
}

TEST(ClothingFitterTest, FitToBodyRejectsABadMesh) {
  OneVertex s = MakeOneVertex();
  const ClothingFitter fitter = *ClothingFitter::Create(s.model, s.correspondence);
  FitScratch scratch;
  Eigen::VectorXf out;
  const Eigen::VectorXf weights = Eigen::Vector2f::Zero();
  std::vector<float> body = Triangle(0, 0);
  body.resize(6);
  EXPECT_THAT(fitter.FitToBody(weights, body, true, scratch, out),
              StatusIs(absl::StatusCode::kInvalidArgument, "the body has 2 vertices"));
  body.push_back(0);
  EXPECT_THAT(fitter.FitToBody(weights, body, true, scratch, out),
              StatusIs(absl::StatusCode::kInvalidArgument, "not a multiple of 3"));
  body = Triangle(0, 0);
  body[4] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THAT(fitter.FitToBody(weights, body, true, scratch, out),
              StatusIs(absl::StatusCode::kInvalidArgument, "vertex 1 has a non-finite"));
  EXPECT_THAT(fitter.FitToBody(Eigen::VectorXf::Zero(5), Triangle(0, 0), true, scratch, out),
              StatusIs(absl::StatusCode::kInvalidArgument, "got 5 avatar weights"));
}

}  // namespace
}  // namespace fitbase::clothing
