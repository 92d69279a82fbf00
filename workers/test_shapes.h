#ifndef FITBASE_WORKERS_TEST_SHAPES_H_
#define FITBASE_WORKERS_TEST_SHAPES_H_

#include <cmath>

#include "core/mesh.h"

namespace fitbase::workers {

// Small closed and open meshes for fast simulator tests. Meters, +y up.

// A UV sphere of `radius` around `center`, outward counter-clockwise triangles as quads and
// pole fans.
inline core::Mesh UvSphere(double radius, int rings = 16, int segments = 24,
                           Eigen::RowVector3d center = Eigen::RowVector3d::Zero()) {
  core::Mesh mesh;
  mesh.positions.resize(2 + (rings - 1) * segments, 3);
  mesh.positions.row(0) = center + Eigen::RowVector3d(0, radius, 0);
  for (int r = 1; r < rings; ++r) {
    const double theta = M_PI * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * M_PI * s / segments;
      mesh.positions.row(1 + (r - 1) * segments + s) =
          center + radius * Eigen::RowVector3d(std::sin(theta) * std::cos(phi), std::cos(theta),
                                               -std::sin(theta) * std::sin(phi));
    }
  }
  const int south = 1 + (rings - 1) * segments;
  mesh.positions.row(south) = center + Eigen::RowVector3d(0, -radius, 0);
  auto ring = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) {
    mesh.faces.sizes.push_back(3);
    mesh.faces.indices.insert(mesh.faces.indices.end(), {0, ring(1, s), ring(1, s + 1)});
  }
  for (int r = 1; r + 1 < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      mesh.faces.sizes.push_back(4);
      mesh.faces.indices.insert(mesh.faces.indices.end(),
                                {ring(r, s), ring(r + 1, s), ring(r + 1, s + 1), ring(r, s + 1)});
    }
  }
  for (int s = 0; s < segments; ++s) {
    mesh.faces.sizes.push_back(3);
    mesh.faces.indices.insert(mesh.faces.indices.end(),
                              {south, ring(rings - 1, s + 1), ring(rings - 1, s)});
  }
  return mesh;
}

// A closed body of revolution around the y axis, `half_height` above and below its waist of
// `waist_radius`, widening away from it like hips and a chest (the sphere's rings at unit
// height y have radius sin(theta) * (waist_radius + flare * y^2)): where a waistband sits.
inline core::Mesh Hourglass(double waist_radius, double flare, double half_height,
                            int rings = 24, int segments = 32) {
  core::Mesh mesh = UvSphere(1.0, rings, segments);
  for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
    const double y = mesh.positions(v, 1);
    const double widen = waist_radius + flare * y * y;
    mesh.positions.row(v) = Eigen::RowVector3d(widen * mesh.positions(v, 0), half_height * y,
                                               widen * mesh.positions(v, 2));
  }
  return mesh;
}

// An open tube (quads) of `radius` around the y axis from y0 (bottom) to y1 (top).
inline core::Mesh Tube(double radius, double y0, double y1, int rows = 8, int segments = 24) {
  core::Mesh mesh;
  mesh.positions.resize((rows + 1) * segments, 3);
  for (int r = 0; r <= rows; ++r) {
    const double y = y0 + (y1 - y0) * r / rows;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * M_PI * s / segments;
      mesh.positions.row(r * segments + s) =
          Eigen::RowVector3d(radius * std::cos(phi), y, -radius * std::sin(phi));
    }
  }
  for (int r = 0; r < rows; ++r) {
    for (int s = 0; s < segments; ++s) {
      const int a = r * segments + s, b = r * segments + (s + 1) % segments;
      mesh.faces.sizes.push_back(4);
      mesh.faces.indices.insert(mesh.faces.indices.end(), {a, b, b + segments, a + segments});
    }
  }
  return mesh;
}

}  // namespace fitbase::workers

#endif  // FITBASE_WORKERS_TEST_SHAPES_H_
