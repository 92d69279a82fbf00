#include "clothing/garment_measure.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "absl/container/flat_hash_map.h"

namespace fitbase::clothing {
namespace {

// Chains of a section closer than this at their ends meet at a seam, m. Seam vertices coincide
// at rest; a fit may part them by a few millimetres.
constexpr double kSeamGap = 0.01;

uint64_t EdgeKey(int32_t a, int32_t b) {
  return (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint32_t>(std::max(a, b));
}

// The rest length of the segment between two section points that cross one triangle: the
// triangle is laid out flat from its three rest edge lengths, and the points keep their
// parameters along their edges, which is exact for the affine map between rest and fitted.
double RestSegment(const body::SectionEdgePoint& p, const body::SectionEdgePoint& q,
                   const absl::flat_hash_map<uint64_t, double>& rest) {
  int32_t corner[3];
  int n = 0;
  for (int32_t v : {p.a, p.b, q.a, q.b}) {
    if (std::find(corner, corner + n, v) == corner + n) {
      if (n == 3) return 0;
      corner[n++] = v;
    }
  }
  if (n != 3) return 0;
  auto length = [&](int32_t a, int32_t b) {
    const auto it = rest.find(EdgeKey(a, b));
    return it == rest.end() ? 0.0 : it->second;
  };
  const double l01 = length(corner[0], corner[1]);
  const double l12 = length(corner[1], corner[2]);
  const double l20 = length(corner[2], corner[0]);
  if (l01 <= 0) return 0;
  const double x2 = (l01 * l01 + l20 * l20 - l12 * l12) / (2 * l01);
  const Eigen::Vector2d flat[3] = {Eigen::Vector2d(0, 0), Eigen::Vector2d(l01, 0),
                                   Eigen::Vector2d(x2, std::sqrt(std::max(0.0, l20 * l20 - x2 * x2)))};
  auto at = [&](const body::SectionEdgePoint& e) {
    const int ia = static_cast<int>(std::find(corner, corner + 3, e.a) - corner);
    const int ib = static_cast<int>(std::find(corner, corner + 3, e.b) - corner);
    return Eigen::Vector2d(flat[ia] + e.t * (flat[ib] - flat[ia]));
  };
  return (at(p) - at(q)).norm();
}

}  // namespace

std::optional<GarmentGirth> GarmentGirthAt(
    const core::Positions& fitted, const core::Triangles& triangles,
    const TriangleEdgeLengths& rest, const body::GirthPlace& place,
    std::span<const Eigen::Vector3d> outside,
    const std::function<bool(const Eigen::Vector3d&)>& counts) {
  const body::PlaneSection section =
      body::SectionMesh(fitted, triangles, place.point, place.normal);
  auto in_plane = [&](const Eigen::Vector3d& x) {
    const Eigen::Vector3d d = x - section.origin;
    return Eigen::Vector2d(d.dot(section.u), d.dot(section.v));
  };

  // Garments are sewn from panels whose seams repeat their vertices, so a section of one
  // breaks into chains ending where the next begins: chains are joined end to end when their
  // ends meet within kSeamGap, and such a junction has no rest length of its own. Points
  // `counts` refuses are dropped (a sleeve beside the chest); the ends this leaves are
  // joined across the gap as a tape bridges it, whatever its length.
  struct Loop {
    std::vector<Eigen::Vector2d> points;
    std::vector<body::SectionEdgePoint> edges;
    std::vector<bool> junction_after;
    bool clipped_front = false;
    bool clipped_back = false;
  };
  std::vector<Loop> loops;
  std::vector<Loop> chains;
  auto kept = [&](const Eigen::Vector2d& q) {
    return !counts || counts(section.origin + q.x() * section.u + q.y() * section.v);
  };
  for (size_t i = 0; i < section.loops.size(); ++i) {
    const auto& points = section.loops[i];
    const size_t n = points.size();
    std::vector<bool> keep(n);
    size_t dropped = 0;
    for (size_t k = 0; k < n; ++k) dropped += !(keep[k] = kept(points[k]));
    if (dropped == n) continue;
    if (dropped == 0) {
      Loop loop{points, section.edges[i], std::vector<bool>(n, false)};
      (section.closed[i] ? loops : chains).push_back(std::move(loop));
      continue;
    }
    // Runs of kept points; a closed loop is walked from just after a dropped point.
    size_t start = 0;
    if (section.closed[i]) {
      while (keep[start]) ++start;
      start = (start + 1) % n;
    }
    const size_t steps = section.closed[i] ? n : n - start;
    Loop run;
    for (size_t s = 0; s <= steps; ++s) {
      const size_t k = (start + s) % n;
      const bool in = s < steps && keep[k];
      if (in) {
        if (run.points.empty()) run.clipped_front = s > 0 || section.closed[i];
        run.points.push_back(points[k]);
        run.edges.push_back(section.edges[i][k]);
        run.junction_after.push_back(false);
      } else if (!run.points.empty()) {
        run.clipped_back = s < steps || section.closed[i];
        chains.push_back(std::move(run));
        run = Loop();
      }
    }
  }
  auto reverse = [](Loop& chain) {
    std::reverse(chain.points.begin(), chain.points.end());
    std::reverse(chain.edges.begin(), chain.edges.end());
    std::swap(chain.clipped_front, chain.clipped_back);
  };
  while (!chains.empty()) {
    Loop chain = std::move(chains.back());
    chains.pop_back();
    for (;;) {
      const double head_gap = (chain.points.back() - chain.points.front()).norm();
      // The nearest end that may join this chain's tail: a seam's partner within kSeamGap, or
      // for a clipped tail the nearest clipped end.
      int next = -1;
      bool reversed = false;
      double nearest = chain.clipped_back ? std::numeric_limits<double>::infinity() : kSeamGap;
      for (size_t c = 0; c < chains.size(); ++c) {
        const double to_front = (chains[c].points.front() - chain.points.back()).norm();
        const double to_back = (chains[c].points.back() - chain.points.back()).norm();
        if (chains[c].clipped_front == chain.clipped_back && to_front < nearest) {
          nearest = to_front, next = static_cast<int>(c), reversed = false;
        }
        if (chains[c].clipped_back == chain.clipped_back && to_back < nearest) {
          nearest = to_back, next = static_cast<int>(c), reversed = true;
        }
      }
      const bool closes = chain.points.size() > 2 && chain.clipped_front == chain.clipped_back &&
                          (chain.clipped_back || head_gap < kSeamGap) && head_gap <= nearest;
      if (closes) {
        chain.junction_after.back() = true;
        loops.push_back(std::move(chain));
        break;
      }
      if (next < 0) break;  // Open: the garment ends here (a slit, or it does not go round).
      Loop other = std::move(chains[next]);
      chains.erase(chains.begin() + next);
      if (reversed) reverse(other);
      chain.junction_after.back() = true;
      chain.points.insert(chain.points.end(), other.points.begin(), other.points.end());
      chain.edges.insert(chain.edges.end(), other.edges.begin(), other.edges.end());
      chain.junction_after.insert(chain.junction_after.end(), other.points.size(), false);
      chain.clipped_back = other.clipped_back;
    }
  }

  const Eigen::Vector2d inside = in_plane(place.inside);
  int best = -1;
  double best_area = 0;
  for (size_t i = 0; i < loops.size(); ++i) {
    const Loop& loop = loops[i];
    if (loop.points.size() < 3 || !body::LoopContains(loop.points, inside)) continue;
    bool excluded = false;
    for (const Eigen::Vector3d& x : outside) {
      excluded |= body::LoopContains(loop.points, in_plane(x));
    }
    if (excluded) continue;
    const double area = body::LoopArea(loop.points);
    if (best < 0 || area < best_area) {
      best = static_cast<int>(i);
      best_area = area;
    }
  }
  if (best < 0) return std::nullopt;

  absl::flat_hash_map<uint64_t, double> rest_of_edge;
  rest_of_edge.reserve(static_cast<size_t>(3 * triangles.rows()));
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    for (int c = 0; c < 3; ++c) {
      rest_of_edge.emplace(EdgeKey(triangles(t, c), triangles(t, (c + 1) % 3)), rest(t, c));
    }
  }
  const Loop& loop = loops[best];
  // Bridged gaps have no material: the loop's stretch is its material's, and its rest length
  // the whole loop's over that stretch.
  double fitted_length = 0;
  double material_fitted = 0;
  double material_rest = 0;
  for (size_t i = 0; i < loop.points.size(); ++i) {
    const size_t j = (i + 1) % loop.points.size();
    const double length = (loop.points[j] - loop.points[i]).norm();
    fitted_length += length;
    if (loop.junction_after[i]) continue;
    material_fitted += length;
    material_rest += RestSegment(loop.edges[i], loop.edges[j], rest_of_edge);
  }
  if (material_rest <= 0) return std::nullopt;
  GarmentGirth girth;
  girth.fitted = body::ConvexHullPerimeter(loop.points);
  girth.stretch = material_fitted / material_rest - 1;
  girth.rest = fitted_length / (1 + girth.stretch);
  return girth;
}

Eigen::VectorXf VertexStretchPercent(const core::Positions& fitted,
                                     const core::Triangles& triangles,
                                     const TriangleEdgeLengths& rest) {
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(fitted.rows());
  Eigen::VectorXd count = Eigen::VectorXd::Zero(fitted.rows());
  // Each interior edge is seen from both its triangles, so it counts twice at both its ends,
  // as a boundary edge counts once: a weighting by the faces around a vertex.
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    for (int c = 0; c < 3; ++c) {
      const int32_t a = triangles(t, c);
      const int32_t b = triangles(t, (c + 1) % 3);
      if (rest(t, c) <= 0) continue;
      const double strain = (fitted.row(a) - fitted.row(b)).norm() / rest(t, c) - 1;
      sum(a) += strain;
      sum(b) += strain;
      count(a) += 1;
      count(b) += 1;
    }
  }
  Eigen::VectorXf percent(fitted.rows());
  for (Eigen::Index v = 0; v < fitted.rows(); ++v) {
    percent(v) = count(v) > 0 ? static_cast<float>(100 * sum(v) / count(v)) : 0.0f;
  }
  return percent;
}

Eigen::VectorXf VertexEaseMm(const core::Positions& fitted, const core::TriangleBvh& body,
                             double max_mm) {
  Eigen::VectorXf ease(fitted.rows());
  for (Eigen::Index v = 0; v < fitted.rows(); ++v) {
    const core::SurfacePoint closest = body.Closest(fitted.row(v).transpose(), max_mm / 1000);
    ease(v) = closest.found ? static_cast<float>(closest.signed_distance * 1000)
                            : static_cast<float>(max_mm);
  }
  return ease;
}

}  // namespace fitbase::clothing
