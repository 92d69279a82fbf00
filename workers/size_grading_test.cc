#include "workers/size_grading.h"

#include <cmath>

#include "gtest/gtest.h"

namespace fitbase::workers {
namespace {

TEST(SizeGradingTest, LengthAlongTheAxisGirthAcross) {
  core::Positions p(4, 3);
  p << 0, 0, 0,  //
      0, 0.1, 0,  // vertical from 0
      0.1, 0, 0,  // horizontal from 0
      0.3, 0.4, 0;  // diagonal from 0
  const core::Positions axes = core::Positions::Zero(4, 3).rowwise() + Eigen::RowVector3d(0, 1, 0);
  const std::vector<std::array<int32_t, 2>> pairs = {{0, 1}, {0, 2}, {0, 3}};
  const Eigen::VectorXd m = GradedRestLengths(p, axes, pairs, 0);
  EXPECT_NEAR(m(0), 0.1, 1e-15);
  EXPECT_NEAR(m(2), 0.5, 1e-15);
  const Eigen::VectorXd l = GradedRestLengths(p, axes, pairs, 1);
  EXPECT_NEAR(l(0), 0.1 * 1.02, 1e-15);
  EXPECT_NEAR(l(1), 0.1 * 1.05, 1e-15);
  EXPECT_NEAR(l(2), std::hypot(0.4 * 1.02, 0.3 * 1.05), 1e-15);
  const Eigen::VectorXd xl = GradedRestLengths(p, axes, pairs, 2);
  EXPECT_NEAR(xl(1), 0.1 * 1.05 * 1.05, 1e-15);
  const Eigen::VectorXd s = GradedRestLengths(p, axes, pairs, -1);
  EXPECT_NEAR(s(1), 0.1 / 1.05, 1e-15);
}

TEST(SizeGradingTest, CancellingAxesCountAsGirth) {
  core::Positions p(2, 3);
  p << 0, 0, 0, 0, 0.1, 0;
  core::Positions axes(2, 3);
  axes << 0, 1, 0, 0, -1, 0;
  EXPECT_NEAR(GradedRestLengths(p, axes, {{0, 1}}, 1)(0), 0.1 * 1.05, 1e-15);
}

}  // namespace
}  // namespace fitbase::workers
