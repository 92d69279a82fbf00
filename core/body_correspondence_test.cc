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
      *BuildBodyCorrespondence(garment, cube.basis, cube.triangles, 0.0025);
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

TEST(BodyCorrespondenceTest, KeepsOnlyTheBodyVerticesItNeeds) {
  const CubeBody cube = MakeCube();
  Positions garment(1, 3);
  garment << 0.1, 0.505, 0.2;
  const BodyCorrespondence correspondence =
      *BuildBodyCorrespondence(garment, cube.basis, cube.triangles, 0.0025);
  EXPECT_EQ(correspondence.body_vertices.size(), 3u);
  EXPECT_EQ(correspondence.body_components.rows(), 9);
  EXPECT_NEAR(correspondence.barycentric.sum(), 1.0f, 1e-6);
}

TEST(BodyCorrespondenceTest, RejectsBadInput) {
  const CubeBody cube = MakeCube();
  Positions garment(1, 3);
  garment << 0.1, std::nan(""), 0.2;
  EXPECT_THAT(BuildBodyCorrespondence(garment, cube.basis, cube.triangles, 0.0025),
              StatusIs(absl::StatusCode::kInvalidArgument, "not finite"));
  garment(0, 1) = 0.6;
  EXPECT_THAT(BuildBodyCorrespondence(garment, cube.basis, cube.triangles, 0),
              StatusIs(absl::StatusCode::kInvalidArgument, "offset"));
  const BodyCorrespondence correspondence =
      *BuildBodyCorrespondence(garment, cube.basis, cube.triangles, 0.0025);
  EXPECT_THAT(ValidateBodyCorrespondence(correspondence, 5, 1),
              StatusIs(absl::StatusCode::kInvalidArgument, "the garment has 5"));
  EXPECT_THAT(ValidateBodyCorrespondence(correspondence, 1, 3),
              StatusIs(absl::StatusCode::kInvalidArgument, "expected 3"));
}

}  // namespace
}  // namespace fitbase::core
