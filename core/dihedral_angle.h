#ifndef FITBASE_CORE_DIHEDRAL_ANGLE_H_
#define FITBASE_CORE_DIHEDRAL_ANGLE_H_

#include "Eigen/Core"

namespace fitbase::core {

// The bending angle of a hinge and its gradient. The hinge is the edge (x0, x1) shared by the
// triangles (x0, x1, x2) and (x0, x1, x3); the angle is 0 when they lie flat in one plane with
// x2 and x3 on opposite sides of the edge, and signed (in (-pi, pi]) by which way they fold.
// It depends only on the points, not on the mesh's face winding.
struct DihedralAngle {
  double angle = 0;  // rad.
  // Column k: d angle / d x_k, rad/m. Zero (and angle 0) for a degenerate hinge.
  Eigen::Matrix<double, 3, 4> gradient = Eigen::Matrix<double, 3, 4>::Zero();
  bool degenerate = true;  // A zero-length edge or a zero-area triangle.
};

// x0..x3: points, m.
DihedralAngle HingeAngle(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1,
                         const Eigen::Vector3d& x2, const Eigen::Vector3d& x3);

}  // namespace fitbase::core

#endif  // FITBASE_CORE_DIHEDRAL_ANGLE_H_
