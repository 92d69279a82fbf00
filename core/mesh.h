#ifndef FITBASE_CORE_MESH_H_
#define FITBASE_CORE_MESH_H_

#include <cstdint>
#include <string>
#include <vector>

#include "Eigen/Core"

namespace fitbase::core {

// Vertex positions, one row per vertex: V x 3, meters unless a function says otherwise.
using Positions = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

// Triangles, one row per triangle: T x 3 vertex indices, counter-clockwise seen from outside.
using Triangles = Eigen::Matrix<int32_t, Eigen::Dynamic, 3, Eigen::RowMajor>;

// Polygon faces in the flat layout of USD and Draco: face f has sizes[f] corners, listed in
// `indices` after those of faces 0..f-1. Garments mix triangles and quads, so no fixed arity.
struct PolygonFaces {
  std::vector<int32_t> sizes;
  std::vector<int32_t> indices;

  int64_t face_count() const { return static_cast<int64_t>(sizes.size()); }
  bool operator==(const PolygonFaces&) const = default;
};

// Splits every polygon into a fan from its first corner, keeping the corner orientation.
Triangles Triangulate(const PolygonFaces& faces);

// (b - a) x (c - a) of triangle t, whose corners a, b, c are rows of positions (V x 3):
// along its normal (outward for a counter-clockwise triangle), twice its area long (m^2).
Eigen::Vector3d TriangleCross(const Positions& positions, const Triangles& triangles,
                              Eigen::Index t);

// Area-weighted vertex normals: V x 3, unit, or zero for a vertex no triangle uses (or whose
// triangles' crosses cancel). triangles: T x 3 rows into positions (V x 3).
Positions VertexNormals(const Positions& positions, const Triangles& triangles);

// positions (V x 3) as 3V floats, xyz interleaved: the layout a body travels in to a fit.
std::vector<float> InterleavedFloats(const Positions& positions);

// A surface mesh whose vertex order is part of its identity: every linear model in fitbase
// relates vertex i of one mesh to vertex i of another of the same topology.
struct Mesh {
  std::string topology_id;
  Positions positions;
  PolygonFaces faces;

  int64_t vertex_count() const { return positions.rows(); }
};

}  // namespace fitbase::core

#endif  // FITBASE_CORE_MESH_H_
