#include "workers/cloth_model.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "Eigen/Geometry"
#include "absl/strings/str_cat.h"
#include "core/dihedral_angle.h"

namespace fitbase::workers {
namespace {

using Pair = std::array<int32_t, 2>;

Pair Sorted(int32_t a, int32_t b) { return a < b ? Pair{a, b} : Pair{b, a}; }

// Union-find root with path halving.
int32_t Root(std::vector<int32_t>& parent, int32_t v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}

// Groups boundary vertices into loops (components of the boundary-edge graph) and keeps, for
// each connected piece of the garment, the loop with the highest mean height.
std::vector<int32_t> TopBoundaryLoops(const core::Positions& positions,
                                      const std::map<Pair, std::vector<int32_t>>& edge_faces,
                                      const core::Triangles& triangles) {
  const int32_t n = static_cast<int32_t>(positions.rows());
  std::vector<int32_t> piece(n), loop(n);
  std::iota(piece.begin(), piece.end(), 0);
  std::iota(loop.begin(), loop.end(), 0);
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    for (int k = 0; k < 3; ++k) {
      piece[Root(piece, triangles(t, k))] = Root(piece, triangles(t, (k + 1) % 3));
    }
  }
  std::vector<bool> on_boundary(n, false);
  for (const auto& [edge, faces] : edge_faces) {
    if (faces.size() != 1) continue;
    on_boundary[edge[0]] = on_boundary[edge[1]] = true;
    loop[Root(loop, edge[0])] = Root(loop, edge[1]);
  }
  // Mean height per loop, then the highest loop per piece.
  std::map<int32_t, std::pair<double, int>> loop_height;
  for (int32_t v = 0; v < n; ++v) {
    if (!on_boundary[v]) continue;
    auto& [sum, count] = loop_height[Root(loop, v)];
    sum += positions(v, 1);
    ++count;
  }
  std::map<int32_t, std::pair<double, int32_t>> best_loop;  // piece -> (height, loop root)
  for (const auto& [root, stats] : loop_height) {
    const double height = stats.first / stats.second;
    const int32_t p = Root(piece, root);
    auto it = best_loop.find(p);
    if (it == best_loop.end() || height > it->second.first) best_loop[p] = {height, root};
  }
  std::vector<int32_t> anchors;
  for (int32_t v = 0; v < n; ++v) {
    if (!on_boundary[v]) continue;
    const auto it = best_loop.find(Root(piece, v));
    if (it != best_loop.end() && it->second.second == Root(loop, v)) anchors.push_back(v);
  }
  return anchors;
}

}  // namespace

absl::StatusOr<ClothModel> BuildClothModel(const core::Positions& positions,
                                           const core::PolygonFaces& faces,
                                           double areal_density) {
  const int64_t n = positions.rows();
  for (int32_t index : faces.indices) {
    if (index < 0 || index >= n) {
      return absl::InvalidArgumentError(
          absl::StrCat("garment face index ", index, " is outside [0, ", n, ")"));
    }
  }
  ClothModel model;
  model.triangles = core::Triangulate(faces);
  if (model.triangles.rows() == 0) return absl::InvalidArgumentError("garment has no faces");

  std::map<Pair, std::vector<int32_t>> edge_faces;
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(n);
  for (Eigen::Index t = 0; t < model.triangles.rows(); ++t) {
    const auto tri = model.triangles.row(t);
    const Eigen::Vector3d a = positions.row(tri(0)), b = positions.row(tri(1)),
                          c = positions.row(tri(2));
    const double third = areal_density * 0.5 * (b - a).cross(c - a).norm() / 3.0;
    for (int k = 0; k < 3; ++k) {
      mass(tri(k)) += third;
      edge_faces[Sorted(tri(k), tri((k + 1) % 3))].push_back(static_cast<int32_t>(t));
    }
  }
  for (const auto& [edge, triangles] : edge_faces) {
    model.edges.push_back(edge);
    if (triangles.size() != 2) continue;
    auto opposite = [&](int32_t t) {
      for (int k = 0; k < 3; ++k) {
        const int32_t v = model.triangles(t, k);
        if (v != edge[0] && v != edge[1]) return v;
      }
      return edge[0];
    };
    const int32_t a = opposite(triangles[0]), b = opposite(triangles[1]);
    if (a != b) model.hinges.push_back({edge[0], edge[1], a, b});
  }
  model.inverse_masses = Eigen::VectorXd::Zero(n);
  for (int64_t v = 0; v < n; ++v) {
    if (mass(v) > 0) model.inverse_masses(v) = 1.0 / mass(v);
  }
  model.anchor_vertices = TopBoundaryLoops(positions, edge_faces, model.triangles);
  return model;
}

Eigen::VectorXd HingeAngles(const core::Positions& positions,
                            const std::vector<std::array<int32_t, 4>>& hinges) {
  Eigen::VectorXd angles(static_cast<Eigen::Index>(hinges.size()));
  for (size_t h = 0; h < hinges.size(); ++h) {
    const auto& v = hinges[h];
    angles(static_cast<Eigen::Index>(h)) =
        core::HingeAngle(positions.row(v[0]), positions.row(v[1]), positions.row(v[2]),
                         positions.row(v[3]))
            .angle;
  }
  return angles;
}

Eigen::VectorXd PairLengths(const core::Positions& positions,
                            const std::vector<std::array<int32_t, 2>>& pairs) {
  Eigen::VectorXd lengths(static_cast<Eigen::Index>(pairs.size()));
  for (size_t e = 0; e < pairs.size(); ++e) {
    lengths(static_cast<Eigen::Index>(e)) =
        (positions.row(pairs[e][0]) - positions.row(pairs[e][1])).norm();
  }
  return lengths;
}

Eigen::VectorXd TriangleRestAreas(const ClothModel& model, const Eigen::VectorXd& edge_rest) {
  auto rest = [&](int32_t i, int32_t j) {
    const auto at = std::lower_bound(model.edges.begin(), model.edges.end(), Sorted(i, j));
    return edge_rest(at - model.edges.begin());
  };
  Eigen::VectorXd areas(model.triangles.rows());
  for (Eigen::Index t = 0; t < model.triangles.rows(); ++t) {
    const auto tri = model.triangles.row(t);
    const double a = rest(tri(0), tri(1)), b = rest(tri(1), tri(2)), c = rest(tri(2), tri(0));
    const double q = (a + b + c) * (-a + b + c) * (a - b + c) * (a + b - c);
    areas(t) = q > 0 ? 0.25 * std::sqrt(q) : 0;
  }
  return areas;
}

}  // namespace fitbase::workers
