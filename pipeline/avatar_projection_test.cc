#include "pipeline/avatar_projection.h"

#include <limits>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::pipeline {
namespace {

using ::testing::HasSubstr;

// Two vertices (D = 6) and two orthonormal components: vertex 0 along x, vertex 1 along y.
LoadedAvatarBasis TinyBasis() {
  LoadedAvatarBasis basis;
  basis.message.set_id("tiny");
  basis.pca.mean = Eigen::VectorXd::LinSpaced(6, 0.0, 0.5);
  basis.pca.components = Eigen::MatrixXd::Zero(6, 2);
  basis.pca.components(0, 0) = 1;
  basis.pca.components(4, 1) = 1;
  basis.pca.variances = Eigen::Vector2d(0.04, 0.01);
  return basis;
}

v1::AvatarWeights Weights(std::initializer_list<double> values) {
  v1::AvatarWeights weights;
  weights.set_basis_id("tiny");
  for (double v : values) weights.add_weights(v);
  return weights;
}

TEST(AvatarProjectionTest, CheckedWeightsKeepsFiniteWeightsOfTheRightCount) {
  const absl::StatusOr<Eigen::VectorXd> w = CheckedWeights(Weights({0.02, -0.01}), 2, "tiny");
  ASSERT_TRUE(w.ok()) << w.status();
  EXPECT_EQ(*w, Eigen::Vector2d(0.02, -0.01));
}

TEST(AvatarProjectionTest, CheckedWeightsNamesAWrongCountAndANonFiniteWeight) {
  const absl::StatusOr<Eigen::VectorXd> short_weights = CheckedWeights(Weights({0.02}), 2, "tiny");
  EXPECT_TRUE(absl::IsInvalidArgument(short_weights.status()));
  EXPECT_THAT(short_weights.status().message(),
              HasSubstr("the weights have 1 components; avatar basis tiny has 2"));
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::infinity()}) {
    const absl::StatusOr<Eigen::VectorXd> w = CheckedWeights(Weights({0.0, bad}), 2, "tiny");
    EXPECT_TRUE(absl::IsInvalidArgument(w.status()));
    EXPECT_THAT(w.status().message(), HasSubstr("weight 1 is not finite"));
  }
}

TEST(AvatarProjectionTest, TheBodyOfItsWeightsProjectsBackToThem) {
  const LoadedAvatarBasis basis = TinyBasis();
  const core::Positions body = BodyOfWeights(basis, Eigen::Vector2d(0.03, -0.02));
  ASSERT_EQ(body.rows(), 2);
  EXPECT_DOUBLE_EQ(body(0, 0), 0.03);  // mean 0 + 0.03 along vertex 0's x.
  EXPECT_DOUBLE_EQ(body(1, 1), 0.4 - 0.02);
  core::Mesh avatar;
  avatar.positions = body;
  const absl::StatusOr<v1::AvatarWeights> projected = ProjectAvatar(basis, avatar);
  ASSERT_TRUE(projected.ok()) << projected.status();
  EXPECT_EQ(projected->basis_id(), "tiny");
  ASSERT_EQ(projected->weights_size(), 2);
  EXPECT_NEAR(projected->weights(0), 0.03, 1e-12);
  EXPECT_NEAR(projected->weights(1), -0.02, 1e-12);
  EXPECT_NEAR(projected->mean_error_mm(), 0.0, 1e-9);

  core::Mesh wrong;
  wrong.positions = core::Positions::Zero(3, 3);
  EXPECT_THAT(ProjectAvatar(basis, wrong).status().message(),
              HasSubstr("avatar has 3 vertices; basis tiny takes 2"));
}

}  // namespace
}  // namespace fitbase::pipeline
