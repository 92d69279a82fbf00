#include "workers/cloth_solver.h"

#include <algorithm>

#include "Eigen/Geometry"
#include <limits>
#include <queue>
#include <utility>

namespace fitbase::workers {
namespace {

// How near a body vertex the body under a garment triangle must be for the triangle to be
// over that vertex: about the body's edge length.
constexpr double kOwnSurfaceRadius = 0.02;
// Body vertices this close to a garment triangle at the start of a step are checked against
// it in every substep of the step.
constexpr double kPokeSearch = 0.01;

}  // namespace

ClothSolver::ClothSolver(const ClothModel& model, const core::Positions& start,
                         Eigen::VectorXd edge_rest, Eigen::VectorXd bend_rest,
                         const core::TriangleBvh& body, const ClothSettings& settings)
    : model_(model),
      settings_(settings),
      edge_rest_(std::move(edge_rest)),
      bend_rest_(std::move(bend_rest)),
      positions_(start),
      previous_(start),
      velocities_(core::Positions::Zero(start.rows(), 3)) {
  for (int32_t v : model.anchor_vertices) {
    const core::SurfacePoint hit = body.Closest(start.row(v).transpose(), 1.0);
    if (!hit.found) continue;
    anchors_.push_back({v, hit.triangle, hit.barycentric, start(v, 1) - hit.point.y()});
  }
  BuildTethers();
  // The model's triangles and the start positions were validated when the model was built.
  garment_bvh_.emplace(*core::TriangleBvh::Build(positions_, model_.triangles));
}

void ClothSolver::BuildTethers() {
  // Multi-source Dijkstra from the anchors over the edges weighted by their rest lengths;
  // ties break on vertex index, so the tethers are deterministic.
  const int32_t n = static_cast<int32_t>(positions_.rows());
  std::vector<std::vector<std::pair<int32_t, double>>> adjacency(n);
  for (size_t e = 0; e < model_.edges.size(); ++e) {
    const auto [i, j] = model_.edges[e];
    adjacency[i].push_back({j, edge_rest_(static_cast<Eigen::Index>(e))});
    adjacency[j].push_back({i, edge_rest_(static_cast<Eigen::Index>(e))});
  }
  std::vector<double> distance(n, std::numeric_limits<double>::infinity());
  std::vector<int32_t> source(n, -1);
  using Entry = std::pair<double, int32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  for (const AnchorBinding& a : anchors_) {
    distance[a.vertex] = 0;
    source[a.vertex] = a.vertex;
    queue.push({0.0, a.vertex});
  }
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[v]) continue;
    for (const auto& [u, length] : adjacency[v]) {
      if (d + length < distance[u]) {
        distance[u] = d + length;
        source[u] = source[v];
        queue.push({distance[u], u});
      }
    }
  }
  for (int32_t v = 0; v < n; ++v) {
    if (source[v] >= 0 && source[v] != v && model_.inverse_masses(v) > 0) {
      tethers_.push_back({v, source[v], distance[v]});
    }
  }
}

double ClothSolver::Step(const core::TriangleBvh& body) {
  const core::Positions before = positions_;
  const double h = settings_.step_seconds / settings_.substeps;
  FindPokes(body);
  floor_ = body.positions().col(1).minCoeff();
  for (int s = 0; s < settings_.substeps; ++s) Substep(body, h);
  return (positions_ - before).rowwise().norm().maxCoeff();
}

void ClothSolver::Substep(const core::TriangleBvh& body, double h) {
  const Eigen::Index n = positions_.rows();
  previous_ = positions_;
  for (Eigen::Index v = 0; v < n; ++v) {
    if (model_.inverse_masses(v) == 0) continue;
    velocities_(v, 1) -= h * settings_.gravity;
    positions_.row(v) += h * velocities_.row(v);
  }
  // With one sweep per substep the Lagrange multipliers start at zero each time, so the XPBD
  // update reduces to -C / (w_i + w_j + alpha / h^2).
  const double h2 = h * h;
  SolvePairs(model_.edges, edge_rest_, settings_.stretch_compliance / h2);
  SolvePairs(model_.bends, bend_rest_, settings_.bend_compliance / h2);
  SolveAnchors(body, settings_.anchor_compliance / h2);
  SolveTethers();
  SolvePokes(body);
  Collide(body, settings_.collision_search, /*with_friction=*/true);
  const double keep = 1.0 - settings_.damping;
  for (Eigen::Index v = 0; v < n; ++v) {
    velocities_.row(v) = keep * (positions_.row(v) - previous_.row(v)) / h;
  }
}

void ClothSolver::SolvePairs(const std::vector<std::array<int32_t, 2>>& pairs,
                             const Eigen::VectorXd& rest, double alpha) {
  const Eigen::VectorXd& w = model_.inverse_masses;
  for (size_t e = 0; e < pairs.size(); ++e) {
    const auto [i, j] = pairs[e];
    const double wsum = w(i) + w(j);
    if (wsum == 0) continue;
    const Eigen::RowVector3d d = positions_.row(i) - positions_.row(j);
    const double length = d.norm();
    if (length < 1e-12) continue;
    const double lambda = -(length - rest(static_cast<Eigen::Index>(e))) / (wsum + alpha);
    const Eigen::RowVector3d correction = (lambda / length) * d;
    positions_.row(i) += w(i) * correction;
    positions_.row(j) -= w(j) * correction;
  }
}

void ClothSolver::SolveAnchors(const core::TriangleBvh& body, double alpha) {
  const core::Positions& p = body.positions();
  const core::Triangles& t = body.triangles();
  for (const AnchorBinding& a : anchors_) {
    const double w = model_.inverse_masses(a.vertex);
    if (w == 0) continue;
    const auto tri = t.row(a.triangle);
    const double surface_y = a.barycentric(0) * p(tri(0), 1) + a.barycentric(1) * p(tri(1), 1) +
                             a.barycentric(2) * p(tri(2), 1);
    const double c = positions_(a.vertex, 1) - (surface_y + a.height_above);
    positions_(a.vertex, 1) += w * (-c / (w + alpha));
  }
}

void ClothSolver::Collide(const core::TriangleBvh& body, double search, bool with_friction) {
  for (Eigen::Index v = 0; v < positions_.rows(); ++v) {
    if (model_.inverse_masses(v) == 0) continue;
    if (positions_(v, 1) < floor_ + settings_.collision_offset) {
      positions_(v, 1) = floor_ + settings_.collision_offset;
      if (with_friction) {
        positions_(v, 0) -= settings_.friction * (positions_(v, 0) - previous_(v, 0));
        positions_(v, 2) -= settings_.friction * (positions_(v, 2) - previous_(v, 2));
      }
    }
    const core::SurfacePoint hit = body.Closest(positions_.row(v).transpose(), search);
    if (!hit.found || hit.signed_distance >= settings_.collision_offset) continue;
    positions_.row(v) = (hit.point + settings_.collision_offset * hit.normal).transpose();
    if (!with_friction) continue;
    // Coulomb-like: remove a share of this substep's slip along the surface.
    const Eigen::Vector3d slip = (positions_.row(v) - previous_.row(v)).transpose();
    const Eigen::Vector3d tangential = slip - slip.dot(hit.normal) * hit.normal;
    positions_.row(v) -= settings_.friction * tangential.transpose();
  }
}

void ClothSolver::FindPokes(const core::TriangleBvh& body) {
  pokes_.clear();
  garment_bvh_->Refit(positions_);
  const core::Positions& bp = body.positions();
  const core::Triangles& bt = body.triangles();
  // Area-weighted body vertex normals: enough to tell outward from inward here.
  core::Positions normals = core::Positions::Zero(bp.rows(), 3);
  for (Eigen::Index t = 0; t < bt.rows(); ++t) {
    const Eigen::RowVector3d n = (bp.row(bt(t, 1)) - bp.row(bt(t, 0)))
                                     .cross(bp.row(bt(t, 2)) - bp.row(bt(t, 0)));
    for (int k = 0; k < 3; ++k) normals.row(bt(t, k)) += n;
  }
  const double reach = kPokeSearch;
  const Eigen::RowVector3d lo = positions_.colwise().minCoeff().array() - reach;
  const Eigen::RowVector3d hi = positions_.colwise().maxCoeff().array() + reach;
  for (Eigen::Index b = 0; b < bp.rows(); ++b) {
    const Eigen::RowVector3d p = bp.row(b);
    if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
    const double norm = normals.row(b).norm();
    if (norm == 0) continue;
    const Eigen::Vector3d n = normals.row(b).transpose() / norm;
    const core::SurfacePoint hit = garment_bvh_->Closest(p.transpose(), reach);
    if (!hit.found) continue;
    // In a crease (armpit, crotch) the triangle may belong to the garment over the facing
    // surface; it is this vertex's only if the body under it is near this vertex.
    const core::SurfacePoint under = body.Closest(hit.point, settings_.collision_search);
    if (!under.found || (under.point - p.transpose()).norm() > kOwnSurfaceRadius) continue;
    pokes_.push_back({static_cast<int32_t>(b), hit.triangle, n});
  }
}

void ClothSolver::SolvePokes(const core::TriangleBvh& body) {
  const double offset = settings_.collision_offset;
  // Each garment vertex takes the largest push any body vertex asks of it: many body vertices
  // under one coarse triangle would otherwise add up their pushes.
  std::vector<std::pair<int32_t, Eigen::RowVector3d>> pushes;
  for (const Poke& poke : pokes_) {
    const Eigen::Vector3d p = body.positions().row(poke.body_vertex).transpose();
    const auto tri = model_.triangles.row(poke.triangle);
    const Eigen::Vector3d a = positions_.row(tri(0)).transpose();
    const Eigen::Vector3d e1 = positions_.row(tri(1)).transpose() - a;
    const Eigen::Vector3d e2 = positions_.row(tri(2)).transpose() - a;
    // Barycentric coordinates of the body vertex's projection on the triangle's plane; only
    // a triangle over the vertex (not one beside it) can be poked through.
    const double d00 = e1.dot(e1), d01 = e1.dot(e2), d11 = e2.dot(e2);
    const double det = d00 * d11 - d01 * d01;
    if (det <= 0) continue;
    const Eigen::Vector3d r = p - a;
    const double v = (d11 * e1.dot(r) - d01 * e2.dot(r)) / det;
    const double w = (d00 * e2.dot(r) - d01 * e1.dot(r)) / det;
    const Eigen::Vector3d bary(1 - v - w, v, w);
    if ((bary.array() < 0).any()) continue;
    const double height = (a + v * e1 + w * e2 - p).dot(poke.normal);
    if (height >= offset) continue;
    double weight_sum = 0;
    for (int k = 0; k < 3; ++k) weight_sum += model_.inverse_masses(tri(k)) * bary(k) * bary(k);
    if (weight_sum == 0) continue;
    const double push = (offset - height) / weight_sum;
    for (int k = 0; k < 3; ++k) {
      pushes.push_back({tri(k), (push * model_.inverse_masses(tri(k)) * bary(k)) *
                                    poke.normal.transpose()});
    }
  }
  // Largest push per vertex, applied in vertex order so the result does not depend on the
  // order the pokes were found in.
  std::stable_sort(pushes.begin(), pushes.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  for (size_t i = 0; i < pushes.size();) {
    size_t j = i;
    Eigen::RowVector3d largest = pushes[i].second;
    for (; j < pushes.size() && pushes[j].first == pushes[i].first; ++j) {
      if (pushes[j].second.squaredNorm() > largest.squaredNorm()) largest = pushes[j].second;
    }
    positions_.row(pushes[i].first) += largest;
    i = j;
  }
}

void ClothSolver::SolveTethers() {
  for (const Tether& t : tethers_) {
    const Eigen::RowVector3d d = positions_.row(t.vertex) - positions_.row(t.anchor);
    const double length = d.norm();
    if (length > t.max_distance) {
      positions_.row(t.vertex) = positions_.row(t.anchor) + (t.max_distance / length) * d;
    }
  }
}

int ClothSolver::ResolveCollisions(const core::TriangleBvh& body, double search) {
  const core::Positions before = positions_;
  floor_ = body.positions().col(1).minCoeff();
  Collide(body, search, /*with_friction=*/false);
  return static_cast<int>(((positions_ - before).rowwise().squaredNorm().array() > 0).count());
}

}  // namespace fitbase::workers
