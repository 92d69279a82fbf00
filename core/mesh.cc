#include "core/mesh.h"

#include "Eigen/Geometry"

namespace fitbase::core {

std::vector<float> InterleavedFloats(const Positions& positions) {
  // Row-major: the rows' coordinates are already interleaved in memory.
  return std::vector<float>(positions.data(), positions.data() + positions.size());
}

Eigen::Vector3d TriangleCross(const Positions& positions, const Triangles& triangles,
                              Eigen::Index t) {
  const Eigen::Vector3d a = positions.row(triangles(t, 0)).transpose();
  const Eigen::Vector3d b = positions.row(triangles(t, 1)).transpose();
  const Eigen::Vector3d c = positions.row(triangles(t, 2)).transpose();
  return (b - a).cross(c - a);
}

Positions VertexNormals(const Positions& positions, const Triangles& triangles) {
  Positions normals = Positions::Zero(positions.rows(), 3);
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    const Eigen::RowVector3d cross = TriangleCross(positions, triangles, t).transpose();
    for (int c = 0; c < 3; ++c) normals.row(triangles(t, c)) += cross;
  }
  for (Eigen::Index v = 0; v < normals.rows(); ++v) {
    const double length = normals.row(v).norm();
    if (length > 0) normals.row(v) /= length;
  }
  return normals;
}

Triangles Triangulate(const PolygonFaces& faces) {
  Eigen::Index count = 0;
  for (int32_t size : faces.sizes) count += size - 2;
  Triangles triangles(count, 3);
  Eigen::Index t = 0;
  size_t corner = 0;
  for (int32_t size : faces.sizes) {
    for (int32_t k = 1; k + 1 < size; ++k) {
      triangles.row(t++) << faces.indices[corner], faces.indices[corner + k],
          faces.indices[corner + k + 1];
    }
    corner += static_cast<size_t>(size);
  }
  return triangles;
}

}  // namespace fitbase::core
