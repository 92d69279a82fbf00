#include "core/dihedral_angle.h"

#include <cmath>

#include "Eigen/Geometry"

namespace fitbase::core {
namespace {

// Below this squared length (m^2) an edge or a doubled triangle area counts as zero.
constexpr double kDegenerate = 1e-20;

}  // namespace

DihedralAngle HingeAngle(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1,
                         const Eigen::Vector3d& x2, const Eigen::Vector3d& x3) {
  DihedralAngle out;
  const Eigen::Vector3d e = x1 - x0;
  const Eigen::Vector3d na = e.cross(x2 - x0);
  const Eigen::Vector3d nb = (x3 - x0).cross(e);
  const double ee = e.squaredNorm(), aa = na.squaredNorm(), bb = nb.squaredNorm();
  if (ee < kDegenerate || aa < kDegenerate * kDegenerate || bb < kDegenerate * kDegenerate) {
    return out;
  }
  const double length = std::sqrt(ee);
  out.degenerate = false;
  out.angle = std::atan2(na.cross(nb).dot(e) / length, na.dot(nb));
  // A wing moves the angle only along its triangle's normal, inversely to its height over
  // the edge; the edge's ends share the opposite of that by the lever rule, which keeps the
  // gradient free of translations and rotations.
  const Eigen::Vector3d g2 = -length / aa * na;
  const Eigen::Vector3d g3 = -length / bb * nb;
  const double a = (x2 - x0).dot(e) / ee;
  const double b = (x3 - x0).dot(e) / ee;
  out.gradient.col(0) = -(1 - a) * g2 - (1 - b) * g3;
  out.gradient.col(1) = -a * g2 - b * g3;
  out.gradient.col(2) = g2;
  out.gradient.col(3) = g3;
  return out;
}

}  // namespace fitbase::core
