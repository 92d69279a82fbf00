#include "core/triangle_bvh.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

#include "Eigen/Geometry"
#include "absl/status/status.h"
#include "absl/strings/str_cat.h"

namespace fitbase::core {
namespace {

// On the MakeHuman body, leaves of up to 2 or 8 triangles made queries slower than 4: tighter
// boxes against fewer triangle tests.
constexpr int32_t kMaxLeafTriangles = 4;

// Median splits halve the triangle count at every level, so a tree over at most 2^31 triangles
// is at most 31 levels deep, and a nearer-first traversal keeps at most one pending sibling per
// level.
constexpr int kMaxStack = 64;

// Rounding makes a triangle's computed distance differ from its box's by a few ulps of the
// coordinates' magnitude. Boxes are kept unless farther than the best distance plus this many
// ulps, so no triangle that could tie with or beat the best is ever pruned: that is what makes
// the answer independent of the tree's shape.
constexpr double kPruneSlackUlps = 64.0;

enum class Feature { kFace, kEdge, kVertex };

// The closest point of one triangle: corner k of a kVertex, side k (corners k, k + 1) of a
// kEdge.
struct TriangleHit {
  Eigen::Vector3d point;
  Eigen::Vector3d barycentric;
  Feature feature = Feature::kFace;
  int k = 0;
};

double Square(double x) { return x * x; }

// Zero when the denominator is: a side of zero length has all its points at the same place.
double SafeRatio(double numerator, double denominator) {
  return denominator > 0.0 ? numerator / denominator : 0.0;
}

// The closest point of the sides of a triangle with no proper interior (collinear or
// coincident corners), where the face formulas divide by zero.
TriangleHit ClosestOnSides(const Eigen::Vector3d& p, const Eigen::Vector3d (&corner)[3]) {
  TriangleHit best{corner[0], Eigen::Vector3d(1.0, 0.0, 0.0), Feature::kVertex, 0};
  double best_d2 = (p - corner[0]).squaredNorm();
  for (int k = 0; k < 3; ++k) {
    const int next = (k + 1) % 3;
    const Eigen::Vector3d side = corner[next] - corner[k];
    const double s = std::clamp(SafeRatio(side.dot(p - corner[k]), side.squaredNorm()), 0.0, 1.0);
    TriangleHit hit{corner[k] + s * side, Eigen::Vector3d::Zero(), Feature::kEdge, k};
    hit.barycentric[k] = 1.0 - s;
    hit.barycentric[next] = s;
    if (s == 0.0 || s == 1.0) {
      hit.feature = Feature::kVertex;
      hit.k = s == 0.0 ? k : next;
    }
    const double d2 = (p - hit.point).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = hit;
    }
  }
  return best;
}

// Ericson, Real-Time Collision Detection, 5.1.5: classifies p by the Voronoi regions of the
// triangle's corners, sides and face, which also names the feature whose pseudo-normal signs
// the distance.
TriangleHit ClosestOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    return TriangleHit{a, Eigen::Vector3d(1.0, 0.0, 0.0), Feature::kVertex, 0};
  }
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) {
    return TriangleHit{b, Eigen::Vector3d(0.0, 1.0, 0.0), Feature::kVertex, 1};
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = SafeRatio(d1, d1 - d3);
    return TriangleHit{a + v * ab, Eigen::Vector3d(1.0 - v, v, 0.0), Feature::kEdge, 0};
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) {
    return TriangleHit{c, Eigen::Vector3d(0.0, 0.0, 1.0), Feature::kVertex, 2};
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = SafeRatio(d2, d2 - d6);
    return TriangleHit{a + w * ac, Eigen::Vector3d(1.0 - w, 0.0, w), Feature::kEdge, 2};
  }
  const double va = d3 * d6 - d5 * d4;
  const double d43 = d4 - d3;
  const double d56 = d5 - d6;
  if (va <= 0.0 && d43 >= 0.0 && d56 >= 0.0) {
    const double w = SafeRatio(d43, d43 + d56);
    return TriangleHit{b + w * (c - b), Eigen::Vector3d(0.0, 1.0 - w, w), Feature::kEdge, 1};
  }
  // va + vb + vc is |ab x ac|^2; for a degenerate triangle the regions above need not cover
  // the outside of the face, so the three weights can come out with mixed signs or zero sum.
  const double sum = va + vb + vc;
  if (!(va >= 0.0 && vb >= 0.0 && vc >= 0.0 && sum > 0.0)) {
    const Eigen::Vector3d corners[3] = {a, b, c};
    return ClosestOnSides(p, corners);
  }
  const double v = vb / sum;
  const double w = vc / sum;
  return TriangleHit{a + v * ab + w * ac, Eigen::Vector3d(1.0 - v - w, v, w), Feature::kFace, 0};
}

}  // namespace

absl::StatusOr<TriangleBvh> TriangleBvh::Build(const Positions& positions,
                                               const Triangles& triangles) {
  if (triangles.rows() == 0) return absl::InvalidArgumentError("TriangleBvh: no triangles");
  if (triangles.rows() > std::numeric_limits<int32_t>::max()) {
    return absl::InvalidArgumentError(
        absl::StrCat("TriangleBvh: ", triangles.rows(), " triangles, more than int32 indexes"));
  }
  for (Eigen::Index v = 0; v < positions.rows(); ++v) {
    if (!positions.row(v).allFinite()) {
      return absl::InvalidArgumentError(
          absl::StrCat("TriangleBvh: position of vertex ", v, " is not finite"));
    }
  }
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int32_t index = triangles(t, k);
      if (index < 0 || index >= positions.rows()) {
        return absl::InvalidArgumentError(absl::StrCat("TriangleBvh: triangle ", t, " corner ", k,
                                                       " has vertex index ", index,
                                                       ", outside [0, ", positions.rows(), ")"));
      }
    }
  }

  TriangleBvh bvh;
  bvh.triangles_ = triangles;
  const auto count = static_cast<int32_t>(triangles.rows());
  bvh.order_.resize(count);
  std::iota(bvh.order_.begin(), bvh.order_.end(), 0);
  // Sums rather than means: the split only compares them.
  std::vector<Eigen::Vector3d> centroids(count);
  for (int32_t t = 0; t < count; ++t) {
    centroids[t] = positions.row(triangles(t, 0)).transpose() +
                   positions.row(triangles(t, 1)).transpose() +
                   positions.row(triangles(t, 2)).transpose();
  }
  bvh.root_ = bvh.BuildSubtree(0, count, centroids);
  bvh.slot_of_.resize(count);
  for (int32_t slot = 0; slot < count; ++slot) bvh.slot_of_[bvh.order_[slot]] = slot;
  bvh.corners_.resize(count);
  bvh.BuildAdjacency(positions.rows());
  bvh.Refit(positions);
  return bvh;
}

TriangleBvh::Child TriangleBvh::BuildSubtree(int32_t begin, int32_t end,
                                             const std::vector<Eigen::Vector3d>& centroids) {
  if (end - begin <= kMaxLeafTriangles) return Child{begin, end - begin};
  Eigen::Vector3d lo = centroids[order_[begin]];
  Eigen::Vector3d hi = lo;
  for (int32_t slot = begin + 1; slot < end; ++slot) {
    lo = lo.cwiseMin(centroids[order_[slot]]);
    hi = hi.cwiseMax(centroids[order_[slot]]);
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  // Ties go to the lower triangle index so that the halves do not depend on the input order
  // std::nth_element happens to see.
  const int32_t mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](int32_t x, int32_t y) {
                     const double cx = centroids[x][axis];
                     const double cy = centroids[y][axis];
                     return cx < cy || (cx == cy && x < y);
                   });
  const auto node = static_cast<int32_t>(nodes_.size());
  nodes_.emplace_back();
  const Child first = BuildSubtree(begin, mid, centroids);
  const Child second = BuildSubtree(mid, end, centroids);
  nodes_[node].child[0] = first;
  nodes_[node].child[1] = second;
  return Child{node, 0};
}

void TriangleBvh::BuildAdjacency(Eigen::Index vertex_count) {
  const auto count = static_cast<int32_t>(triangles_.rows());
  // Sorting the sides by their undirected vertex pair gathers the sides of each edge; the sort
  // order also numbers the edges deterministically.
  std::vector<std::pair<uint64_t, int32_t>> sides;
  sides.reserve(3 * static_cast<size_t>(count));
  for (int32_t t = 0; t < count; ++t) {
    for (int k = 0; k < 3; ++k) {
      const auto u = static_cast<uint32_t>(triangles_(t, k));
      const auto v = static_cast<uint32_t>(triangles_(t, (k + 1) % 3));
      const uint64_t key = (static_cast<uint64_t>(std::min(u, v)) << 32) | std::max(u, v);
      sides.emplace_back(key, 3 * t + k);
    }
  }
  std::sort(sides.begin(), sides.end());
  triangle_edges_.resize(count);
  edge_triangles_.reserve(sides.size());
  int32_t edge = -1;
  for (size_t i = 0; i < sides.size(); ++i) {
    if (i == 0 || sides[i].first != sides[i - 1].first) {
      ++edge;
      edge_offsets_.push_back(static_cast<int32_t>(i));
    }
    const int32_t side = sides[i].second;
    triangle_edges_[side / 3][side % 3] = edge;
    edge_triangles_.push_back(side / 3);
  }
  edge_offsets_.push_back(static_cast<int32_t>(sides.size()));

  vertex_offsets_.assign(vertex_count + 1, 0);
  for (int32_t t = 0; t < count; ++t) {
    for (int k = 0; k < 3; ++k) ++vertex_offsets_[triangles_(t, k) + 1];
  }
  std::partial_sum(vertex_offsets_.begin(), vertex_offsets_.end(), vertex_offsets_.begin());
  vertex_corners_.resize(3 * static_cast<size_t>(count));
  std::vector<int32_t> next(vertex_offsets_.begin(), vertex_offsets_.end() - 1);
  for (int32_t t = 0; t < count; ++t) {
    for (int k = 0; k < 3; ++k) vertex_corners_[next[triangles_(t, k)]++] = 3 * t + k;
  }
}

void TriangleBvh::Refit(const Positions& positions) {
  assert(positions.rows() + 1 == static_cast<Eigen::Index>(vertex_offsets_.size()));
  positions_ = positions;
  for (size_t slot = 0; slot < order_.size(); ++slot) {
    const int32_t t = order_[slot];
    corners_[slot] = Corners{positions_.row(triangles_(t, 0)).transpose(),
                             positions_.row(triangles_(t, 1)).transpose(),
                             positions_.row(triangles_(t, 2)).transpose()};
  }
  coordinate_bound_ = positions_.cwiseAbs().maxCoeff();
  // Children follow their parent, so a reverse sweep sees both before the parent.
  for (auto node = static_cast<int32_t>(nodes_.size()) - 1; node >= 0; --node) {
    Node& n = nodes_[node];
    for (int i = 0; i < 2; ++i) {
      const Child child = n.child[i];
      Eigen::Vector3d lo;
      Eigen::Vector3d hi;
      if (child.count > 0) {
        lo = corners_[child.index].a;
        hi = lo;
        for (int32_t slot = child.index; slot < child.index + child.count; ++slot) {
          const Corners& c = corners_[slot];
          lo = lo.cwiseMin(c.a).cwiseMin(c.b).cwiseMin(c.c);
          hi = hi.cwiseMax(c.a).cwiseMax(c.b).cwiseMax(c.c);
        }
      } else {
        const Node& grandchildren = nodes_[child.index];
        for (int axis = 0; axis < 3; ++axis) {
          lo[axis] = grandchildren.lo[axis].minCoeff();
          hi[axis] = grandchildren.hi[axis].maxCoeff();
        }
      }
      for (int axis = 0; axis < 3; ++axis) {
        n.lo[axis][i] = lo[axis];
        n.hi[axis][i] = hi[axis];
      }
    }
  }
}

Eigen::Vector3d TriangleBvh::EdgeNormal(int32_t t, int k) const {
  const int32_t edge = triangle_edges_[t][k];
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int32_t i = edge_offsets_[edge]; i < edge_offsets_[edge + 1]; ++i) {
    sum += TriangleCross(positions_, triangles_, edge_triangles_[i]).normalized();
  }
  return sum.normalized();
}

Eigen::Vector3d TriangleBvh::VertexNormal(int32_t t, int k) const {
  const int32_t vertex = triangles_(t, k);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int32_t i = vertex_offsets_[vertex]; i < vertex_offsets_[vertex + 1]; ++i) {
    const int32_t other = vertex_corners_[i] / 3;
    const int corner = vertex_corners_[i] % 3;
    const Eigen::Vector3d cross = TriangleCross(positions_, triangles_, other);
    const double twice_area = cross.norm();
    if (twice_area == 0.0) continue;
    const Eigen::Vector3d p = positions_.row(vertex).transpose();
    const Eigen::Vector3d to_next =
        positions_.row(triangles_(other, (corner + 1) % 3)).transpose() - p;
    const Eigen::Vector3d to_prev =
        positions_.row(triangles_(other, (corner + 2) % 3)).transpose() - p;
    // |to_next x to_prev| is twice the area too; atan2 stays accurate for angles near 0 and pi.
    const double angle = std::atan2(twice_area, to_next.dot(to_prev));
    sum += (angle / twice_area) * cross;
  }
  return sum.normalized();
}

SurfacePoint TriangleBvh::Closest(const Eigen::Vector3d& query, double max_distance,
                                  int32_t hint) const {
  SurfacePoint result;
  result.barycentric.setZero();
  result.point.setZero();
  result.normal.setZero();
  if (!query.allFinite() || !(max_distance >= 0.0)) return result;

  const double slack = kPruneSlackUlps * std::numeric_limits<double>::epsilon() *
                       (coordinate_bound_ + query.cwiseAbs().maxCoeff());
  double best2 = Square(max_distance);
  double limit2 = Square(max_distance + slack);
  int32_t best_triangle = -1;
  TriangleHit best_hit{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Feature::kFace, 0};

  // The hint is the best so far only as the traversal would have found it: it wins ties only
  // against higher rows, which the traversal below still checks against it.
  if (hint >= 0 && hint < triangles_.rows()) {
    const int32_t slot = slot_of_[hint];
    const Corners& c = corners_[slot];
    const TriangleHit hit = ClosestOnTriangle(query, c.a, c.b, c.c);
    const double d2 = (query - hit.point).squaredNorm();
    if (d2 <= best2) {
      best2 = d2;
      best_triangle = hint;
      best_hit = hit;
      limit2 = Square(std::sqrt(best2) + slack);
    }
  }

  struct Entry {
    Child child;
    double d2;
  };
  Entry stack[kMaxStack];
  int size = 0;
  stack[size++] = Entry{root_, 0.0};
  while (size > 0) {
    const Entry entry = stack[--size];
    if (!(entry.d2 <= limit2)) continue;
    if (entry.child.count > 0) {
      for (int32_t slot = entry.child.index; slot < entry.child.index + entry.child.count; ++slot) {
        const Corners& c = corners_[slot];
        const TriangleHit hit = ClosestOnTriangle(query, c.a, c.b, c.c);
        const double d2 = (query - hit.point).squaredNorm();
        const int32_t t = order_[slot];
        if (d2 < best2 || (d2 == best2 && (best_triangle < 0 || t < best_triangle))) {
          best2 = d2;
          best_triangle = t;
          best_hit = hit;
          limit2 = Square(std::sqrt(best2) + slack);
        }
      }
      continue;
    }
    const Node& node = nodes_[entry.child.index];
    Eigen::Array2d d2 = Eigen::Array2d::Zero();
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Array2d gap =
          (node.lo[axis] - query[axis]).max(query[axis] - node.hi[axis]).max(0.0);
      d2 += gap * gap;
    }
    // The nearer child goes on top so that it tightens the bound before the other is opened.
    const int nearer = d2[1] < d2[0] ? 1 : 0;
    const int farther = 1 - nearer;
    if (d2[farther] <= limit2) stack[size++] = Entry{node.child[farther], d2[farther]};
    if (d2[nearer] <= limit2) stack[size++] = Entry{node.child[nearer], d2[nearer]};
  }
  if (best_triangle < 0) return result;

  const auto face = [&] {
    return TriangleCross(positions_, triangles_, best_triangle).normalized();
  };
  Eigen::Vector3d normal;
  if (best_hit.feature == Feature::kEdge) {
    normal = EdgeNormal(best_triangle, best_hit.k);
  } else if (best_hit.feature == Feature::kVertex) {
    normal = VertexNormal(best_triangle, best_hit.k);
  } else {
    normal = face();
  }
  // A feature whose own normals cancel or vanish (folded or degenerate triangles) borrows the
  // closest triangle's face normal; where that vanishes too there is no side to tell, and the
  // offset direction is the only normal a collision response can use.
  if (normal.squaredNorm() == 0.0) normal = face();
  if (normal.squaredNorm() == 0.0) normal = (query - best_hit.point).normalized();
  const double distance = std::sqrt(best2);
  result.found = true;
  result.triangle = best_triangle;
  result.barycentric = best_hit.barycentric;
  result.point = best_hit.point;
  result.normal = normal;
  result.signed_distance = (query - best_hit.point).dot(normal) < 0.0 ? -distance : distance;
  return result;
}

}  // namespace fitbase::core
