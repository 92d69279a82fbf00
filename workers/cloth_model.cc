#include "workers/cloth_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

#include "Eigen/Eigenvalues"
#include "Eigen/Geometry"
#include "absl/strings/str_cat.h"
#include "body/body_measurements.h"
#include "body/body_model.h"
#include "core/dihedral_angle.h"
#include "core/mesh.h"
#include "core/status_macros.h"

namespace fitbase::workers {
namespace {

using Pair = std::array<int32_t, 2>;

Pair Sorted(int32_t a, int32_t b) { return a < b ? Pair{a, b} : Pair{b, a}; }

// Union-find root with path halving.
int32_t Root(std::vector<int32_t>& parent, int32_t v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}

// FindSupports and FindCuffs read the hm08 body's landmarks.
absl::Status CheckMeanBody(const core::Positions& mean_body) {
  if (mean_body.rows() != body::kBodyVertexCount) {
    return absl::InvalidArgumentError(absl::StrCat("the mean avatar has ", mean_body.rows(),
                                                   " vertices, not ", body::kBodyVertexCount));
  }
  return absl::OkStatus();
}

// Groups boundary edges into loops (components of the boundary-edge graph), each with its
// piece (component of the triangle graph); marks each piece's loop with its highest vertex.
std::vector<Opening> BoundaryLoops(const core::Positions& positions,
                                   const std::vector<Pair>& edges,
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
  std::vector<int32_t> boundary_edges;
  for (size_t e = 0; e < edges.size(); ++e) {
    if (edge_faces.at(edges[e]).size() != 1) continue;
    boundary_edges.push_back(static_cast<int32_t>(e));
    loop[Root(loop, edges[e][0])] = Root(loop, edges[e][1]);
  }
  // Loops in the order of their lowest vertex, pieces numbered in the order of theirs.
  std::map<int32_t, size_t> loop_index;
  std::map<int32_t, int32_t> piece_index;
  std::vector<Opening> openings;
  std::vector<bool> on_boundary(n, false);
  for (int32_t e : boundary_edges) on_boundary[edges[e][0]] = on_boundary[edges[e][1]] = true;
  for (int32_t v = 0; v < n; ++v) {
    if (on_boundary[v]) piece_index.try_emplace(Root(piece, v), piece_index.size());
  }
  for (int32_t v = 0; v < n; ++v) {
    if (!on_boundary[v]) continue;
    const auto [it, added] = loop_index.try_emplace(Root(loop, v), openings.size());
    if (added) {
      openings.push_back({.vertices = {}, .edges = {}, .piece = piece_index.at(Root(piece, v))});
    }
    Opening& opening = openings[it->second];
    opening.vertices.push_back(v);
    opening.mean_height += positions(v, 1);
  }
  for (int32_t e : boundary_edges) {
    openings[loop_index.at(Root(loop, edges[e][0]))].edges.push_back(e);
  }
  // By the highest vertex, not the mean height: a bib overall's top edge runs down its sides
  // to the waist, and the buttonholes at the top of its bib are higher on average.
  std::map<int32_t, std::pair<double, size_t>> highest;  // piece -> (top height, opening)
  for (size_t o = 0; o < openings.size(); ++o) {
    Opening& opening = openings[o];
    opening.mean_height /= static_cast<double>(opening.vertices.size());
    double top = -std::numeric_limits<double>::infinity();
    for (int32_t v : opening.vertices) top = std::max(top, positions(v, 1));
    const auto [it, added] = highest.try_emplace(opening.piece, top, o);
    if (!added && top > it->second.first) it->second = {top, o};
  }
  for (const auto& [p, top] : highest) openings[top.second].highest_of_piece = true;
  return openings;
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
    const double third =
        areal_density * 0.5 * core::TriangleCross(positions, model.triangles, t).norm() / 3.0;
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
  model.openings = BoundaryLoops(positions, model.edges, edge_faces, model.triangles);
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

bool Supports::IsWaistband(const Opening& opening) const {
  return !opening.edges.empty() && std::binary_search(waistband_edges.begin(),
                                                      waistband_edges.end(), opening.edges[0]);
}

bool Supports::IsCollar(int32_t opening) const {
  return std::binary_search(collars.begin(), collars.end(), opening);
}

bool Supports::IsStrap(int32_t opening) const {
  return std::binary_search(straps.begin(), straps.end(), opening);
}

absl::StatusOr<Supports> FindSupports(const ClothModel& model, const core::Positions& garment,
                                      const core::Positions& mean_body) {
  using body::BodyLandmarks;
  RETURN_IF_ERROR(CheckMeanBody(mean_body));
  if (garment.rows() != model.inverse_masses.size()) {
    return absl::InvalidArgumentError(absl::StrCat("the garment has ", garment.rows(),
                                                   " vertices, its cloth model ",
                                                   model.inverse_masses.size()));
  }
  const double crotch = mean_body(BodyLandmarks::kCrotch, 1);
  const double underbust = mean_body(BodyLandmarks::kLeftUnderbust, 1);
  const Eigen::Vector2d torso_axis(mean_body(BodyLandmarks::kCrotch, 0),
                                   mean_body(BodyLandmarks::kCrotch, 2));
  const Eigen::Vector2d neck_axis(
      0.5 * (mean_body(BodyLandmarks::kNeckFront, 0) + mean_body(BodyLandmarks::kNeckBack, 0)),
      0.5 * (mean_body(BodyLandmarks::kNeckFront, 2) + mean_body(BodyLandmarks::kNeckBack, 2)));
  // Even-odd rule in the x-z plane, which needs neither the loop's order nor its edges'
  // orientation: a loop round the axis crosses the ray from it towards +x an odd number of
  // times, one beside it (a front edge and the hem behind the axis) an even number.
  auto rings = [&](const Opening& opening, const Eigen::Vector2d& axis) {
    int crossings = 0;
    for (int32_t e : opening.edges) {
      const auto [a, b] = model.edges[e];
      const double za = garment(a, 2) - axis.y(), zb = garment(b, 2) - axis.y();
      if ((za > 0) == (zb > 0)) continue;
      const double x = garment(a, 0) + (garment(b, 0) - garment(a, 0)) * za / (za - zb);
      crossings += x > axis.x();
    }
    return crossings % 2 == 1;
  };
  Supports supports;
  for (size_t o = 0; o < model.openings.size(); ++o) {
    const Opening& opening = model.openings[o];
    if (!opening.highest_of_piece || opening.mean_height <= crotch) continue;
    if (opening.mean_height >= underbust) {
      if (!rings(opening, neck_axis)) continue;
      double lowest = std::numeric_limits<double>::infinity();
      for (int32_t v : opening.vertices) lowest = std::min(lowest, garment(v, 1));
      (lowest >= underbust ? supports.collars : supports.straps)
          .push_back(static_cast<int32_t>(o));
    } else if (rings(opening, torso_axis)) {
      supports.waistband_edges.insert(supports.waistband_edges.end(), opening.edges.begin(),
                                      opening.edges.end());
    }
  }
  std::sort(supports.waistband_edges.begin(), supports.waistband_edges.end());
  return supports;
}

absl::StatusOr<std::vector<int32_t>> FindCuffs(const ClothModel& model,
                                               const core::Positions& garment,
                                               const std::vector<body::BodyRegion>& regions,
                                               const core::Positions& mean_body,
                                               const core::Triangles& body_triangles,
                                               CuffDeclaration declared) {
  RETURN_IF_ERROR(CheckMeanBody(mean_body));
  const Eigen::Index n = model.inverse_masses.size();
  if (garment.rows() != n || static_cast<Eigen::Index>(regions.size()) != n) {
    return absl::InvalidArgumentError(absl::StrCat("the garment has ", garment.rows(),
                                                   " vertices and ", regions.size(),
                                                   " vertex regions, its cloth model ", n));
  }
  std::vector<int32_t> cuffs;
  if (!declared.sleeves && !declared.legs) return cuffs;
  // A T-shirt's hem over the hips covers mostly the thighs' region, and rings the hips.
  const double crotch = mean_body(body::BodyLandmarks::kCrotch, 1);
  for (size_t o = 0; o < model.openings.size(); ++o) {
    const Opening& opening = model.openings[o];
    if (opening.highest_of_piece || opening.vertices.size() < 3) continue;
    int arms = 0, legs = 0;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int32_t v : opening.vertices) {
      const body::BodyRegion region = regions[v];
      arms += region == body::BodyRegion::kArms;
      legs += region == body::BodyRegion::kLegs || region == body::BodyRegion::kFeet;
      centre += garment.row(v).transpose();
    }
    const int half = static_cast<int>(opening.vertices.size()) / 2;
    centre /= static_cast<double>(opening.vertices.size());
    const bool sleeve = declared.sleeves && arms > half;
    const bool leg = declared.legs && legs > half && centre.y() < crotch;
    if (!sleeve && !leg) continue;
    // The limb is cut across where the opening lies: in its best-fitting plane, whose normal
    // is the direction its vertices spread least in.
    Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
    for (int32_t v : opening.vertices) {
      const Eigen::Vector3d d = garment.row(v).transpose() - centre;
      spread += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> axes(spread);
    // NaN when no loop of the section goes round the centre: the opening rings no one limb.
    const double limb_girth = body::GirthAround(
        body::SectionMesh(mean_body, body_triangles, centre, axes.eigenvectors().col(0)), centre);
    if (std::isfinite(limb_girth)) cuffs.push_back(static_cast<int32_t>(o));
  }
  return cuffs;
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
