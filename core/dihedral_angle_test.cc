#include "core/dihedral_angle.h"

#include <array>
#include <cmath>

#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A hinge along x whose wings make `fold` rad with the flat position, folding up about the
// edge; the wings sit at different places along the edge so the lever rule is exercised.
std::array<Eigen::Vector3d, 4> Hinge(double fold) {
  return {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
          Eigen::Vector3d(0.3, 0.8, 0),
          Eigen::Vector3d(0.7, -0.5 * std::cos(fold), 0.5 * std::sin(fold))};
}

TEST(HingeAngle, IsZeroWhenFlatAndSignedByTheFold) {
  const auto flat = Hinge(0);
  EXPECT_NEAR(HingeAngle(flat[0], flat[1], flat[2], flat[3]).angle, 0, 1e-15);
  const auto up = Hinge(0.4), down = Hinge(-0.4);
  const double a = HingeAngle(up[0], up[1], up[2], up[3]).angle;
  EXPECT_NEAR(std::abs(a), 0.4, 1e-12);
  EXPECT_NEAR(HingeAngle(down[0], down[1], down[2], down[3]).angle, -a, 1e-12);
  // The same points in the other order along the edge fold the other way round.
  EXPECT_NEAR(HingeAngle(up[1], up[0], up[3], up[2]).angle, a, 1e-12);
}

TEST(HingeAngle, GradientMatchesFiniteDifferences) {
  for (double fold : {0.0, 0.3, -1.2, 2.5}) {
    auto x = Hinge(fold);
    const DihedralAngle h = HingeAngle(x[0], x[1], x[2], x[3]);
    ASSERT_FALSE(h.degenerate);
    const double step = 1e-7;
    for (int k = 0; k < 4; ++k) {
      for (int d = 0; d < 3; ++d) {
        auto plus = x, minus = x;
        plus[k](d) += step;
        minus[k](d) -= step;
        const double numeric = (HingeAngle(plus[0], plus[1], plus[2], plus[3]).angle -
                                HingeAngle(minus[0], minus[1], minus[2], minus[3]).angle) /
                               (2 * step);
        EXPECT_NEAR(h.gradient(d, k), numeric, 1e-6)
            << "fold " << fold << " x" << k << "[" << d << "]";
      }
    }
  }
}

TEST(HingeAngle, NearlyClosedHingeStaysInRange) {
  const auto x = Hinge(kPi - 1e-3);
  const double a = HingeAngle(x[0], x[1], x[2], x[3]).angle;
  EXPECT_GT(std::abs(a), kPi - 2e-3);
  EXPECT_LE(std::abs(a), kPi);
}

TEST(HingeAngle, DegenerateHingeHasNoGradient) {
  const Eigen::Vector3d o(0, 0, 0), p(1, 0, 0);
  const DihedralAngle h = HingeAngle(o, o, p, Eigen::Vector3d(0, 1, 0));
  EXPECT_TRUE(h.degenerate);
  EXPECT_EQ(h.gradient.norm(), 0);
  EXPECT_TRUE(HingeAngle(o, p, Eigen::Vector3d(2, 0, 0), Eigen::Vector3d(0, 1, 0)).degenerate);
}

}  // namespace
}  // namespace fitbase::core
