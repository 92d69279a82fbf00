#include "core/body_correspondence.h"

#include <cmath>

#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

// The cube [-0.5, 0.5]^3 (m) as a body, with one component: a rigid lift along +y.
struct CubeBody {
  PcaBasis basis;
  Triangles triangles;
};

CubeBody MakeCube() {
  CubeBody cube;
  Positions corners(8, 3);
  for (int i = 0; i < 8; ++i) {
    corners.row(i) << (i & 1 ? 0.5 : -0.5), (i & 2 ? 0.5 : -0.5), (i & 4 ? 0.5 : -0.5);
  }
  cube.triangles.resize(12, 3);
  cube.triangles << 0, 2, 1, 1, 2, 3,  // z = -0.5
      4, 5, 6, 5, 7, 6,                // z = +0.5
      0, 1, 4, 1, 5, 4,                // y = -0.5
      2, 6, 3, 3, 6, 7,                // y = +0.5
      0, 4, 2, 2, 4, 6,                // x = -0.5
      1, 3, 5, 3, 7, 5;                // x = +0.5
  cube.basis.mean = Eigen::Map<const Eigen::VectorXd>(corners.data(), 24);
  cube.basis.components = Eigen::MatrixXd::Zero(24, 1);
  for (int i = 0; i < 8; ++i) cube.basis.components(3 * i + 1, 0) = 1 / std::sqrt(8.0);
  cube.basis.variances = Eigen::VectorXd::Constant(1, 1e-4);
  return cube;
}

TEST(BodyCorrespondenceTest, PushesOutOnlyTheVerticesTheCustomerBodyReaches) {
  const CubeBody cube = MakeCube();
  Positions garment(2, 3);
  garment << 0.1, 0.505, 0.2,  // 5 mm above the top face.
      0.6, 0.0, 0.1;           // 10 cm beside the +x face.
  const BodyCorrespondence correspondence =
      *BuildBodyCorrespondence({{&garment, Eigen::VectorXd::Zero(1)}}, cube.basis, cube.triangles,
                               0.0025, 1);
  EXPECT_TRUE(ValidateBodyCorrespondence(correspondence, 2, 1).ok());

  Eigen::VectorXf lift(1);
  lift << static_cast<float>(0.02 * std::sqrt(8.0));  // The body rises by 2 cm.
  Eigen::VectorXf positions = Eigen::Map<const Eigen::VectorXd>(garment.data(), 6).cast<float>();
  Eigen::VectorXf body;
  EXPECT_EQ(PushOutOfBody(correspondence, lift, body, positions.data()), 1);
  EXPECT_NEAR(positions(1), 0.5 + 0.02 + 0.0025, 1e-6);
  EXPECT_NEAR(positions(0), 0.1, 1e-7);
  EXPECT_NEAR(positions(2), 0.2, 1e-7);
  EXPECT_EQ(positions.tail<3>(), garment.row(1).transpose().cast<float>());

  // At the mean body nothing is inside: the fit is left as it is.
  positions = Eigen::Map<const Eigen::VectorXd>(garment.data(), 6).cast<float>();
  EXPECT_EQ(PushOutOfBody(correspondence, Eigen::VectorXf::Zero(1), body, positions.data()), 0);
}

// At the mean the vertex sits beside the +x face; in an example with the body lowered by 0.4 m
// it sits on the top face. A customer lowered by 0.395 m has the fitted vertex 1 mm inside the
// top: only the anchor from the second example sees that; the mean's anchor alone would push
// the vertex 20 cm sideways out of the +x face's plane.
TEST(BodyCorrespondenceTest, AnchorsFromExamplesFollowASlidingVertex) {
  const CubeBody cube = MakeCube();
  Positions at_mean(1, 3), lowered(1, 3);
  at_mean << 0.503, 0.3, 0.0;
  lowered << 0.3, 0.103, 0.0;
  const double sqrt8 = std::sqrt(8.0);
  const BodyCorrespondence correspondence = *BuildBodyCorrespondence(
      {{&at_mean, Eigen::VectorXd::Zero(1)}, {&lowered, Eigen::VectorXd::Constant(1, -0.4 * sqrt8)}},
      cube.basis, cube.triangles, 0.0025, 2);
  EXPECT_EQ(correspondence.anchors_per_vertex, 2);
  EXPECT_TRUE(ValidateBodyCorrespondence(correspondence, 1, 1).ok());
  Eigen::VectorXf positions = Eigen::Vector3f(0.3f, 0.104f, 0.0f);
  Eigen::VectorXf body;
  const Eigen::VectorXf customer = Eigen::VectorXf::Constant(1, static_cast<float>(-0.395 * sqrt8));
  EXPECT_EQ(PushOutOfBody(correspondence, customer, body, positions.data()), 1);
  EXPECT_NEAR(positions(1), 0.105 + 0.0025, 1e-6);
  EXPECT_NEAR(positions(0), 0.3, 1e-6);
}

TEST(BodyCorrespondenceTest, KeepsOnlyTheBodyVerticesItNeeds) {
  const CubeBody cube = MakeCube();
  Positions garment(1, 3);
  garment << 0.1, 0.505, 0.2;
  const BodyCorrespondence correspondence = *BuildBodyCorrespondence(
      {{&garment, Eigen::VectorXd::Zero(1)}}, cube.basis, cube.triangles, 0.0025, 1);
  EXPECT_EQ(correspondence.body_vertices.size(), 3u);
  EXPECT_EQ(correspondence.body_components.rows(), 9);
  EXPECT_NEAR(correspondence.barycentric.sum(), 1.0f, 1e-6);
}

TEST(BodyCorrespondenceTest, RejectsBadInput) {
  const CubeBody cube = MakeCube();
  Positions garment(1, 3);
  garment << 0.1, std::nan(""), 0.2;
  const std::vector<CorrespondenceExample> examples = {{&garment, Eigen::VectorXd::Zero(1)}};
  EXPECT_THAT(BuildBodyCorrespondence(examples, cube.basis, cube.triangles, 0.0025, 1),
              StatusIs(absl::StatusCode::kInvalidArgument, "not finite"));
  garment(0, 1) = 0.6;
  EXPECT_THAT(BuildBodyCorrespondence(examples, cube.basis, cube.triangles, 0, 1),
              StatusIs(absl::StatusCode::kInvalidArgument, "offset"));
  EXPECT_THAT(BuildBodyCorrespondence(examples, cube.basis, cube.triangles, 0.0025, 0),
              StatusIs(absl::StatusCode::kInvalidArgument, "anchors per vertex"));
  const BodyCorrespondence correspondence =
      *BuildBodyCorrespondence(examples, cube.basis, cube.triangles, 0.0025, 1);
  EXPECT_THAT(ValidateBodyCorrespondence(correspondence, 5, 1),
              StatusIs(absl::StatusCode::kInvalidArgument, "the garment has 5 vertices"));
  EXPECT_THAT(ValidateBodyCorrespondence(correspondence, 1, 3),
              StatusIs(absl::StatusCode::kInvalidArgument, "expected 3"));
}

}  // namespace
}  // namespace fitbase::core
