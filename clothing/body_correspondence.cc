#include "clothing/body_correspondence.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <utility>

#include "Eigen/Geometry"
#include "absl/strings/str_cat.h"
#include "core/matrix_vector.h"
#include "core/mesh.h"
#include "core/status_macros.h"
#include "core/triangle_bvh.h"

namespace fitbase::clothing {

namespace {

// A triangle a garment vertex was closest to, how often, and where first.
struct AnchorCount {
  int32_t triangle;
  int count;
  int first_example;
  Eigen::Vector3f barycentric;
};

// A garment triangle a body vertex lay under, how often, and whether its corners must swap for
// their normal to point away from the body (as first seen).
struct GuardCount {
  int32_t triangle;
  int count;
  bool flip;
};

// One more sighting of `first.triangle`: its count goes up, or it is kept as first seen.
template <typename Count>
void CountTriangle(std::vector<Count>& seen, const Count& first) {
  auto it = std::find_if(seen.begin(), seen.end(),
                         [&](const Count& c) { return c.triangle == first.triangle; });
  if (it != seen.end()) {
    ++it->count;
  } else {
    seen.push_back(first);
  }
}

// A body point this far (m) outside a garment triangle's plane is not under it: a fit that far
// off has the triangle in another place of the body, and its plane says nothing there.
constexpr float kGuardDepth = static_cast<float>(kGuardReach);
// A guard's point may project this far (barycentric) outside its triangle: the point between
// two guarded triangles whose projections leave a gap on a convex garment is still caught.
constexpr float kGuardSlack = 0.05f;

// Garment triangles a body vertex lay under (closest drape point within kGuardReach, on the
// outer side of the skin) in one example: counted into seen[body vertex].
void CountGuards(const core::Positions& body, const core::Triangles& body_triangles,
                 const std::vector<bool>& skin, const core::TriangleBvh& garment,
                 std::vector<std::vector<GuardCount>>& seen) {
  const core::Positions normals = core::VertexNormals(body, body_triangles);
  for (Eigen::Index b = 0; b < body.rows(); ++b) {
    if (!skin[b]) continue;
    const Eigen::Vector3d p = body.row(b).transpose();
    const core::SurfacePoint closest = garment.Closest(p, kGuardReach);
    if (!closest.found) continue;
    const Eigen::Vector3d up = closest.point - p;
    const Eigen::Vector3d n = normals.row(b).transpose();
    // Beside a hem the closest drape point lies along the skin, not over it.
    if (up.dot(n) < 0.5 * up.norm()) continue;
    const Eigen::Vector3d face =
        core::TriangleCross(garment.positions(), garment.triangles(), closest.triangle);
    CountTriangle(seen[b], GuardCount{closest.triangle, 1, face.dot(n) < 0});
  }
}

// A point as four floats in one vector register (xyz and a zero pad), with GCC and Clang
// vector extensions: SSE on x86-64, NEON on ARM. Eigen 3.4's Vector4f::cross3 is scalar and
// round-trips through memory, which stalled the clean-up's two passes over every vertex and
// guard; these keep them in registers (the fit: 1.4 to 1.6 times faster).
typedef float F4 __attribute__((vector_size(16)));

F4 LoadF4(const float* p) {
  F4 result;
  std::memcpy(&result, p, sizeof(result));
  return result;
}

float Dot(F4 a, F4 b) {
  const F4 product = a * b;
  return (product[0] + product[1]) + product[2];
}

F4 Cross(F4 a, F4 b) {
  const F4 a_yzx = __builtin_shufflevector(a, a, 1, 2, 0, 3);
  const F4 b_yzx = __builtin_shufflevector(b, b, 1, 2, 0, 3);
  const F4 c = a * b_yzx - a_yzx * b;
  return __builtin_shufflevector(c, c, 1, 2, 0, 3);
}

// Lane j: the sum of the xyz lanes of v[j] (a 4x4 transpose folded into the additions).
F4 SumLanes(const F4 v[4]) {
  const F4 low01 = __builtin_shufflevector(v[0], v[1], 0, 4, 1, 5);
  const F4 high01 = __builtin_shufflevector(v[0], v[1], 2, 6, 3, 7);
  const F4 low23 = __builtin_shufflevector(v[2], v[3], 0, 4, 1, 5);
  const F4 high23 = __builtin_shufflevector(v[2], v[3], 2, 6, 3, 7);
  const F4 x01z01 = __builtin_shufflevector(low01, high01, 0, 1, 4, 5);
  const F4 y01w01 = __builtin_shufflevector(low01, high01, 2, 3, 6, 7);
  const F4 x23z23 = __builtin_shufflevector(low23, high23, 0, 1, 4, 5);
  const F4 y23w23 = __builtin_shufflevector(low23, high23, 2, 3, 6, 7);
  const F4 xz = __builtin_shufflevector(x01z01, x23z23, 0, 1, 4, 5);
  const F4 y = __builtin_shufflevector(y01w01, y23w23, 0, 1, 4, 5);
  const F4 z = __builtin_shufflevector(x01z01, x23z23, 2, 3, 6, 7);
  return (xz + y) + z;
}

// Point i of a field of 4-float points (xyz and a zero pad), 16-byte aligned.
Eigen::Map<Eigen::Vector4f, Eigen::Aligned16> Point4(float* field, int32_t i) {
  return Eigen::Map<Eigen::Vector4f, Eigen::Aligned16>(field + 4 * static_cast<Eigen::Index>(i));
}

// Adds what `request` still lacks to the displacement field (4 floats per vertex), shared among
// its corners in proportion to their weights: the least-squares change that meets it.
void Apply(const ClearanceRequest& request, float* field) {
  float current = 0;
  float weight_squares = 0;
  for (int i = 0; i < 3; ++i) {
    if (request.weights[i] == 0) continue;
    current += request.weights[i] * Point4(field, request.vertices[i]).dot(request.normal);
    weight_squares += request.weights[i] * request.weights[i];
  }
  if (!(current < request.amount)) return;
  const float step = (request.amount - current) / weight_squares;
  for (int i = 0; i < 3; ++i) {
    if (request.weights[i] == 0) continue;
    Point4(field, request.vertices[i]) += (request.weights[i] * step) * request.normal;
  }
}

// Body points padded to 4 floats (w = 0) for aligned loads; points: 3U, body4: 4U.
void PadBodyPoints(const Eigen::VectorXf& points, Eigen::VectorXf& body4) {
  const Eigen::Index u = points.size() / 3;
  if (body4.size() != 4 * u) body4.setZero(4 * u);
  for (Eigen::Index i = 0; i < u; ++i) body4.segment<3>(4 * i) = points.segment<3>(3 * i);
}

// One Jacobi round of averaging a field of 4-float points over the garment's edges: each of
// the V vertices' points in `to` becomes the mean of its own and its neighbours' in `from`.
// Every vertex in index order, reading what the previous round wrote: no vertex waits for
// another's new value, as in a Gauss-Seidel sweep, so a round runs at the speed of the loads.
void AverageOverNeighbors(const BodyCorrespondence& correspondence, const float* from, float* to) {
  const int32_t* offsets = correspondence.neighbor_offsets.data();
  const int32_t* neighbors = correspondence.neighbors.data();
  const Eigen::Index vertex_count = correspondence.vertex_count();
  for (Eigen::Index v = 0; v < vertex_count; ++v) {
    F4 sum = LoadF4(from + 4 * v);
    for (int32_t n = offsets[v]; n < offsets[v + 1]; ++n) {
      sum += LoadF4(from + 4 * static_cast<Eigen::Index>(neighbors[n]));
    }
    const F4 mean = sum / static_cast<float>(1 + offsets[v + 1] - offsets[v]);
    std::memcpy(to + 4 * v, &mean, sizeof(mean));
  }
}

// The row of garment vertex v's anchor nearest g among its K, on the padded body points.
Eigen::Index NearestAnchor(const BodyCorrespondence& correspondence, const float* body4,
                           const F4& g, Eigen::Index v) {
  const int k = correspondence.anchors_per_vertex;
  const int32_t* anchor_corners = correspondence.corners.data();
  const float* anchor_barycentric = correspondence.barycentric.data();
  const auto point4 = [&](int32_t i) { return LoadF4(body4 + 4 * static_cast<Eigen::Index>(i)); };
  const auto anchor4 = [&](Eigen::Index r) {
    const int32_t* c = anchor_corners + 3 * r;
    const float* b = anchor_barycentric + 3 * r;
    return b[0] * point4(c[0]) + b[1] * point4(c[1]) + b[2] * point4(c[2]);
  };
  // Anchors four at a time, their squared distances summed across lanes together; a last
  // group short of four repeats the vertex's first anchor, which never wins a tie.
  Eigen::Index nearest = v * k;
  float best = std::numeric_limits<float>::infinity();
  for (Eigen::Index r0 = v * k; r0 < (v + 1) * k; r0 += 4) {
    Eigen::Index rows[4];
    F4 squares[4];
    for (int j = 0; j < 4; ++j) {
      rows[j] = r0 + j < (v + 1) * k ? r0 + j : v * k;
      const F4 d = g - anchor4(rows[j]);
      squares[j] = d * d;
    }
    const F4 distances = SumLanes(squares);
    for (int j = 0; j < 4; ++j) {
      nearest = distances[j] < best ? rows[j] : nearest;
      best = distances[j] < best ? distances[j] : best;
    }
  }
  return nearest;
}

// Garment vertex v (at g) against its nearest anchor's triangle on the padded body points:
// the anchor's row, a corner of the triangle and (b - a) x (c - a), unnormalized. Only the
// nearest anchor's plane is needed, so its normal is computed once, not per anchor.
struct AnchorPlane {
  Eigen::Index row;
  F4 corner;
  F4 cross;
};

AnchorPlane PlaneOfAnchor(const BodyCorrespondence& correspondence, const float* body4,
                          Eigen::Index row) {
  const int32_t* c = correspondence.corners.data() + 3 * row;
  const auto point4 = [&](int32_t i) { return LoadF4(body4 + 4 * static_cast<Eigen::Index>(i)); };
  const F4 a = point4(c[0]);
  return {row, a, Cross(point4(c[1]) - a, point4(c[2]) - a)};
}

// Each garment vertex's nearest anchor (rows: V) for positions (3V floats, m) on the padded
// body points. A pass of its own: a vertex's search and what is made of its anchor after are
// one long chain of dependent loads and arithmetic, and with both in one loop too few
// vertices were in flight at once to hide it (male_casualsuit01, 8.4k vertices: FollowBody's
// pass took 196 us).
void NearestAnchors(const BodyCorrespondence& correspondence, const float* body4,
                    const float* positions, std::vector<int32_t>& rows) {
  const Eigen::Index vertex_count = correspondence.vertex_count();
  rows.resize(static_cast<size_t>(vertex_count));
  for (Eigen::Index v = 0; v < vertex_count; ++v) {
    const float* gv = positions + 3 * v;
    rows[static_cast<size_t>(v)] =
        static_cast<int32_t>(NearestAnchor(correspondence, body4, F4{gv[0], gv[1], gv[2], 0}, v));
  }
}

// The tree of the body under the garment, current for this clean-up: the correspondence's
// body_triangles over its body points (`body`, 3U floats, m). Refitted when it holds that
// topology (a thread's fits of one garment share it), else built.
absl::StatusOr<const core::TriangleBvh*> CurrentBodyTree(const BodyCorrespondence& correspondence,
                                                         const Eigen::VectorXf& body,
                                                         CleanupScratch& scratch) {
  std::optional<core::TriangleBvh>& tree = scratch.body_tree;
  if (scratch.body_tree_current) return &*tree;
  core::Positions& positions = scratch.body_tree_positions;
  positions = Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>>(
                  body.data(), body.size() / 3, 3)
                  .cast<double>();
  // Finite weights can still overflow the body of the weights, far outside any body.
  if (!positions.allFinite()) {
    return absl::InvalidArgumentError("a body point under the garment is not finite");
  }
  const core::Triangles& triangles = correspondence.body_triangles;
  if (tree && tree->positions().rows() == positions.rows() &&
      tree->triangles().rows() == triangles.rows() &&
      std::equal(triangles.data(), triangles.data() + triangles.size(), tree->triangles().data())) {
    tree->Refit(positions);
  } else {
    tree.reset();
    ASSIGN_OR_RETURN(core::TriangleBvh built, core::TriangleBvh::Build(positions, triangles));
    tree = std::move(built);
  }
  scratch.body_tree_current = true;
  return &*tree;
}

}  // namespace

absl::Status SetGarmentNeighbors(const core::Triangles& garment_triangles,
                                 BodyCorrespondence& correspondence) {
  const int64_t vertex_count = correspondence.vertex_count();
  std::vector<std::pair<int32_t, int32_t>> edges;
  edges.reserve(6 * static_cast<size_t>(garment_triangles.rows()));
  for (Eigen::Index t = 0; t < garment_triangles.rows(); ++t) {
    for (int c = 0; c < 3; ++c) {
      const int32_t a = garment_triangles(t, c);
      const int32_t b = garment_triangles(t, (c + 1) % 3);
      if (a < 0 || a >= vertex_count || b < 0 || b >= vertex_count) {
        return absl::InvalidArgumentError(absl::StrCat(
            "garment triangle ", t, " has a corner outside [0, ", vertex_count, ")"));
      }
      if (a == b) continue;
      edges.emplace_back(a, b);
      edges.emplace_back(b, a);
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  correspondence.neighbor_offsets.assign(static_cast<size_t>(vertex_count) + 1, 0);
  correspondence.neighbors.clear();
  correspondence.neighbors.reserve(edges.size());
  for (const auto& [from, to] : edges) {
    ++correspondence.neighbor_offsets[from + 1];
    correspondence.neighbors.push_back(to);
  }
  for (int64_t v = 0; v < vertex_count; ++v) {
    correspondence.neighbor_offsets[v + 1] += correspondence.neighbor_offsets[v];
  }
  return absl::OkStatus();
}

absl::StatusOr<BodyCorrespondence> BuildBodyCorrespondence(
    const std::vector<CorrespondenceExample>& examples, const core::PcaBasis& avatar,
    const core::Triangles& body_triangles, const core::Triangles& garment_triangles, double offset,
    int anchors_per_vertex) {
  if (!std::isfinite(offset) || offset <= 0) {
    return absl::InvalidArgumentError(absl::StrCat("clean-up offset must be > 0 m, got ", offset));
  }
  if (anchors_per_vertex < 1) {
    return absl::InvalidArgumentError(
        absl::StrCat("anchors per vertex must be >= 1, got ", anchors_per_vertex));
  }
  if (examples.empty()) return absl::InvalidArgumentError("no example drapes to anchor");
  const Eigen::Index vertex_count = examples[0].garment->rows();
  for (const CorrespondenceExample& e : examples) {
    if (e.garment->rows() != vertex_count || vertex_count == 0 || !e.garment->allFinite()) {
      return absl::InvalidArgumentError("example drapes are empty, not finite or of different sizes");
    }
    if (e.weights.size() > avatar.components.cols() || !e.weights.allFinite()) {
      return absl::InvalidArgumentError("example weights do not fit the avatar basis");
    }
  }
  const core::Positions mean =
      Eigen::Map<const core::Positions>(avatar.mean.data(), avatar.mean.size() / 3, 3);
  ASSIGN_OR_RETURN(core::TriangleBvh bvh, core::TriangleBvh::Build(mean, body_triangles));
  const bool guarded = garment_triangles.rows() > 0;
  std::optional<core::TriangleBvh> garment_bvh;
  std::vector<bool> skin(static_cast<size_t>(mean.rows()), false);
  if (guarded) {
    if (garment_triangles.minCoeff() < 0 || garment_triangles.maxCoeff() >= vertex_count) {
      return absl::InvalidArgumentError(absl::StrCat("garment triangle corner outside [0, ",
                                                     vertex_count, ")"));
    }
    ASSIGN_OR_RETURN(garment_bvh,
                     core::TriangleBvh::Build(*examples[0].garment, garment_triangles));
    for (int32_t i : body_triangles.reshaped()) skin[i] = true;
  }
  std::vector<std::vector<GuardCount>> guards_seen(guarded ? skin.size() : 0);

  std::vector<std::vector<AnchorCount>> seen(vertex_count);
  for (size_t e = 0; e < examples.size(); ++e) {
    const Eigen::VectorXd body = core::ReconstructFromWeights(avatar, examples[e].weights);
    const Eigen::Map<const core::Positions> body_positions(body.data(), body.size() / 3, 3);
    bvh.Refit(body_positions);
    if (guarded) {
      garment_bvh->Refit(*examples[e].garment);
      CountGuards(body_positions, body_triangles, skin, *garment_bvh, guards_seen);
    }
    for (Eigen::Index v = 0; v < vertex_count; ++v) {
      const core::SurfacePoint closest = bvh.Closest(examples[e].garment->row(v).transpose(),
                                               std::numeric_limits<double>::infinity());
      if (!closest.found) return absl::InternalError("no closest body point for a garment vertex");
      CountTriangle(seen[v], AnchorCount{closest.triangle, 1, static_cast<int>(e),
                                         closest.barycentric.cast<float>()});
    }
  }

  BodyCorrespondence result;
  result.offset = offset;
  result.anchors_per_vertex = anchors_per_vertex;
  const Eigen::Index rows = vertex_count * anchors_per_vertex;
  std::vector<int32_t> triangles(rows);
  result.barycentric.resize(rows, 3);
  for (Eigen::Index v = 0; v < vertex_count; ++v) {
    std::vector<AnchorCount>& anchors = seen[v];
    std::stable_sort(anchors.begin(), anchors.end(), [](const AnchorCount& a, const AnchorCount& b) {
      return a.count > b.count;
    });
    for (int k = 0; k < anchors_per_vertex; ++k) {
      const AnchorCount& a = anchors[k < static_cast<int>(anchors.size()) ? k : 0];
      triangles[v * anchors_per_vertex + k] = a.triangle;
      result.barycentric.row(v * anchors_per_vertex + k) = a.barycentric.transpose();
      for (int c = 0; c < 3; ++c) result.body_vertices.push_back(body_triangles(a.triangle, c));
    }
  }
  std::vector<std::pair<int32_t, Eigen::RowVector3i>> guards;
  for (size_t b = 0; b < guards_seen.size(); ++b) {
    std::vector<GuardCount>& counts = guards_seen[b];
    // Most frequent first; ties keep the order seen, the earlier example first.
    std::stable_sort(counts.begin(), counts.end(), [](const GuardCount& x, const GuardCount& y) {
      return x.count > y.count;
    });
    for (size_t k = 0; k < counts.size() && k < static_cast<size_t>(kGuardsPerBodyVertex); ++k) {
      Eigen::RowVector3i corners = garment_triangles.row(counts[k].triangle);
      if (counts[k].flip) std::swap(corners[1], corners[2]);
      guards.emplace_back(static_cast<int32_t>(b), corners);
      result.body_vertices.push_back(static_cast<int32_t>(b));
    }
  }
  std::sort(result.body_vertices.begin(), result.body_vertices.end());
  result.body_vertices.erase(std::unique(result.body_vertices.begin(), result.body_vertices.end()),
                             result.body_vertices.end());

  const Eigen::Index u = static_cast<Eigen::Index>(result.body_vertices.size());
  result.body_mean.resize(3 * u);
  result.body_components.resize(3 * u, avatar.components.cols());
  for (Eigen::Index i = 0; i < u; ++i) {
    const Eigen::Index row = 3 * static_cast<Eigen::Index>(result.body_vertices[i]);
    result.body_mean.segment<3>(3 * i) = avatar.mean.segment<3>(row).cast<float>();
    result.body_components.middleRows<3>(3 * i) = avatar.components.middleRows<3>(row).cast<float>();
  }
  const auto row_of = [&](int32_t body_vertex) {
    return static_cast<int32_t>(std::lower_bound(result.body_vertices.begin(),
                                                 result.body_vertices.end(), body_vertex) -
                                result.body_vertices.begin());
  };
  result.corners.resize(rows, 3);
  for (Eigen::Index r = 0; r < rows; ++r) {
    for (int c = 0; c < 3; ++c) result.corners(r, c) = row_of(body_triangles(triangles[r], c));
  }
  result.guard_triangles.resize(static_cast<Eigen::Index>(guards.size()), 3);
  for (size_t g = 0; g < guards.size(); ++g) {
    result.guard_body.push_back(row_of(guards[g].first));
    result.guard_triangles.row(static_cast<Eigen::Index>(g)) = guards[g].second;
  }
  std::vector<int32_t> region;
  for (Eigen::Index t = 0; t < body_triangles.rows(); ++t) {
    const Eigen::RowVector3i corners = body_triangles.row(t);
    if (std::all_of(corners.begin(), corners.end(), [&](int32_t b) {
          return std::binary_search(result.body_vertices.begin(), result.body_vertices.end(), b);
        })) {
      for (int32_t b : corners) region.push_back(row_of(b));
    }
  }
  result.body_triangles = Eigen::Map<const core::Triangles>(
      region.data(), static_cast<Eigen::Index>(region.size() / 3), 3);
  if (guarded) {
    result.smoothing_iterations = kSmoothingIterations;
    RETURN_IF_ERROR(SetGarmentNeighbors(garment_triangles, result));
  }
  return result;
}

absl::Status ValidateBodyCorrespondence(const BodyCorrespondence& correspondence,
                                        int64_t garment_vertex_count, int component_count) {
  const Eigen::Index u = static_cast<Eigen::Index>(correspondence.body_vertices.size());
  const int64_t k = correspondence.anchors_per_vertex;
  if (k < 1 || correspondence.corners.rows() != garment_vertex_count * k ||
      correspondence.barycentric.rows() != garment_vertex_count * k) {
    return absl::InvalidArgumentError(
        absl::StrCat("body correspondence has ", correspondence.corners.rows(), " anchors, ", k,
                     " per vertex; the garment has ", garment_vertex_count, " vertices"));
  }
  if (correspondence.body_mean.size() != 3 * u || correspondence.body_components.rows() != 3 * u ||
      correspondence.body_components.cols() != component_count) {
    return absl::InvalidArgumentError(
        absl::StrCat("body correspondence has ", correspondence.body_components.cols(),
                     " components over ", u, " vertices; expected ", component_count));
  }
  if (!std::isfinite(correspondence.offset) || correspondence.offset <= 0 ||
      !correspondence.body_mean.allFinite() || !correspondence.body_components.allFinite() ||
      !correspondence.barycentric.allFinite()) {
    return absl::InvalidArgumentError("body correspondence is not finite");
  }
  if (garment_vertex_count > 0 &&
      (correspondence.corners.minCoeff() < 0 || correspondence.corners.maxCoeff() >= u)) {
    return absl::InvalidArgumentError("body correspondence corner out of range");
  }
  const Eigen::Index guards = correspondence.guard_triangles.rows();
  if (static_cast<Eigen::Index>(correspondence.guard_body.size()) != guards) {
    return absl::InvalidArgumentError(absl::StrCat("body correspondence has ",
                                                   correspondence.guard_body.size(),
                                                   " guard body points for ", guards,
                                                   " guard triangles"));
  }
  for (int32_t b : correspondence.guard_body) {
    if (b < 0 || b >= u) {
      return absl::InvalidArgumentError(
          absl::StrCat("body correspondence guard body point ", b, " outside [0, ", u, ")"));
    }
  }
  if (guards > 0 && (correspondence.guard_triangles.minCoeff() < 0 ||
                     correspondence.guard_triangles.maxCoeff() >= garment_vertex_count)) {
    return absl::InvalidArgumentError(absl::StrCat(
        "body correspondence guard triangle corner outside [0, ", garment_vertex_count, ")"));
  }
  const core::Triangles& body_triangles = correspondence.body_triangles;
  if (body_triangles.rows() > 0 &&
      (body_triangles.minCoeff() < 0 || body_triangles.maxCoeff() >= u)) {
    return absl::InvalidArgumentError(
        absl::StrCat("body correspondence body triangle corner outside [0, ", u, ")"));
  }
  if (correspondence.smoothing_iterations < 0 ||
      correspondence.smoothing_iterations > kMaxSmoothingIterations) {
    return absl::InvalidArgumentError(
        absl::StrCat("body correspondence smoothing iterations ",
                     correspondence.smoothing_iterations, " outside [0, ",
                     kMaxSmoothingIterations, "]"));
  }
  const std::vector<int32_t>& offsets = correspondence.neighbor_offsets;
  const std::vector<int32_t>& neighbors = correspondence.neighbors;
  if (offsets.empty()) {
    if (!neighbors.empty() || correspondence.smoothing_iterations > 0) {
      return absl::InvalidArgumentError(
          "body correspondence smooths but has no garment neighbour lists");
    }
    return absl::OkStatus();
  }
  if (static_cast<int64_t>(offsets.size()) != garment_vertex_count + 1 || offsets.front() != 0 ||
      offsets.back() != static_cast<int64_t>(neighbors.size()) ||
      !std::is_sorted(offsets.begin(), offsets.end())) {
    return absl::InvalidArgumentError(absl::StrCat(
        "body correspondence neighbour lists do not match ", garment_vertex_count, " vertices"));
  }
  for (int32_t n : neighbors) {
    if (n < 0 || n >= garment_vertex_count) {
      return absl::InvalidArgumentError(absl::StrCat(
          "body correspondence neighbour ", n, " outside [0, ", garment_vertex_count, ")"));
    }
  }
  return absl::OkStatus();
}

void BodyPointsOfWeights(const BodyCorrespondence& correspondence,
                         const Eigen::VectorXf& weights, Eigen::VectorXf& points) {
  points = correspondence.body_mean;
  core::MultiplyAccumulate(correspondence.body_components, weights, points);
}

absl::Status GatherBodyPoints(const BodyCorrespondence& correspondence,
                              std::span<const float> avatar, Eigen::VectorXf& points) {
  if (avatar.size() % 3 != 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("the body has ", avatar.size(), " coordinates, not a multiple of 3"));
  }
  const int64_t avatar_vertices = static_cast<int64_t>(avatar.size() / 3);
  const Eigen::Index u = static_cast<Eigen::Index>(correspondence.body_vertices.size());
  points.resize(3 * u);
  for (Eigen::Index i = 0; i < u; ++i) {
    const int64_t b = correspondence.body_vertices[i];
    if (b < 0 || b >= avatar_vertices) {
      return absl::InvalidArgumentError(
          absl::StrCat("the body has ", avatar_vertices, " vertices; the garment's clean-up uses ",
                       "vertex ", b, ": not the avatar topology the garment was built on"));
    }
    for (int c = 0; c < 3; ++c) {
      const float x = avatar[static_cast<size_t>(3 * b + c)];
      if (!std::isfinite(x)) {
        return absl::InvalidArgumentError(
            absl::StrCat("body vertex ", b, " has a non-finite coordinate"));
      }
      points(3 * i + c) = x;
    }
  }
  return absl::OkStatus();
}

void FollowBody(const BodyCorrespondence& correspondence, const Eigen::VectorXf& fitted_for,
                const Eigen::VectorXf& body, CleanupScratch& scratch, float* positions) {
  Eigen::VectorXf& from4 = scratch.body4;
  PadBodyPoints(fitted_for, from4);
  const Eigen::Index vertex_count = correspondence.vertex_count();
  // Padded to 4 floats (w = 0), so that the rounds below add whole points in one vector
  // operation each.
  Eigen::VectorXf& field = scratch.follow;
  field.setZero(4 * vertex_count);
  // How far each body point moved, padded like the points.
  Eigen::VectorXf& moved4 = scratch.moved4;
  const Eigen::Index u = body.size() / 3;
  if (moved4.size() != 4 * u) moved4.setZero(4 * u);
  for (Eigen::Index i = 0; i < u; ++i) {
    moved4.segment<3>(4 * i) = body.segment<3>(3 * i) - fitted_for.segment<3>(3 * i);
  }
  const auto body_moved = [&](int32_t i) {
    return LoadF4(moved4.data() + 4 * static_cast<Eigen::Index>(i));
  };
  NearestAnchors(correspondence, from4.data(), positions, scratch.anchor_rows);
  for (Eigen::Index v = 0; v < vertex_count; ++v) {
    const AnchorPlane plane =
        PlaneOfAnchor(correspondence, from4.data(), scratch.anchor_rows[static_cast<size_t>(v)]);
    const F4 cross = plane.cross;
    const float area2 = Dot(cross, cross);
    if (!(area2 > 0)) continue;
    const int32_t* c = correspondence.corners.data() + 3 * plane.row;
    const float* b = correspondence.barycentric.data() + 3 * plane.row;
    const F4 moved = b[0] * body_moved(c[0]) + b[1] * body_moved(c[1]) + b[2] * body_moved(c[2]);
    const F4 carried = (Dot(moved, cross) / area2) * cross;
    std::memcpy(field.data() + 4 * v, &carried, sizeof(carried));
  }
  // Jacobi rounds of averaging over each vertex's garment neighbours: cloth bridges the
  // body's fine detail, which the projection leaves out too.
  Eigen::VectorXf& next = scratch.follow_next;
  for (int round = 0;
       round < kFollowSmoothingIterations && !correspondence.neighbor_offsets.empty(); ++round) {
    next.resize(field.size());
    AverageOverNeighbors(correspondence, field.data(), next.data());
    field.swap(next);
  }
  for (Eigen::Index v = 0; v < vertex_count; ++v) {
    for (int c = 0; c < 3; ++c) positions[3 * v + c] += field[4 * v + c];
  }
}

absl::StatusOr<int64_t> PushOutOfBody(const BodyCorrespondence& correspondence,
                                      const Eigen::VectorXf& weights, CleanupScratch& scratch,
                                      float* positions) {
  BodyPointsOfWeights(correspondence, weights, scratch.body);
  return PushOutOfBodyPoints(correspondence, scratch.body, {}, scratch, positions);
}

absl::StatusOr<int64_t> PushOutOfBodyPoints(const BodyCorrespondence& correspondence,
                                            const Eigen::VectorXf& body,
                                            std::span<const int32_t> anchor_rows,
                                            CleanupScratch& scratch, float* positions) {
  scratch.body_tree_current = false;
  scratch.deep_checks = 0;
  const float offset = static_cast<float>(correspondence.offset);
  const Eigen::Index vertex_count = correspondence.vertex_count();
  auto& requests = scratch.requests;
  requests.clear();
  requests.reserve(static_cast<size_t>(vertex_count + correspondence.guard_triangles.rows()));
  Eigen::VectorXf& body4 = scratch.body4;
  PadBodyPoints(body, body4);
  const auto point4 = [&](int32_t i) {
    return LoadF4(body4.data() + 4 * static_cast<Eigen::Index>(i));
  };
  if (anchor_rows.empty()) {
    NearestAnchors(correspondence, body4.data(), positions, scratch.anchor_rows);
    anchor_rows = scratch.anchor_rows;
  }
  for (Eigen::Index v = 0; v < vertex_count; ++v) {
    const float* gv = positions + 3 * v;
    const F4 g = {gv[0], gv[1], gv[2], 0};
    const AnchorPlane plane =
        PlaneOfAnchor(correspondence, body4.data(), anchor_rows[static_cast<size_t>(v)]);
    const F4 cross = plane.cross;
    const float area2 = Dot(cross, cross);
    if (!(area2 > 0)) continue;
    // The anchor lies in its triangle's plane, so the height is measured from a corner; times
    // |cross|, so that a vertex clear of the plane is passed over without a root or a division.
    const float scaled = Dot(g - plane.corner, cross);
    if (scaled >= 0 && scaled * scaled >= offset * offset * area2) continue;
    const float length = std::sqrt(area2);
    const F4 normal = cross / length;
    const int32_t i = static_cast<int32_t>(v);
    const Eigen::Vector4f along_anchor(normal[0], normal[1], normal[2], 0);
    // Vertex i moved `amount` along `direction` (unit, w = 0).
    const auto push = [&](const Eigen::Vector4f& direction, float amount) {
      requests.push_back({{i, i, i}, {1, 0, 0}, direction, amount});
    };
    if (correspondence.body_triangles.rows() > 0 && -scaled > kDeepPush * length) {
      ++scratch.deep_checks;
      ASSIGN_OR_RETURN(const core::TriangleBvh* tree,
                       CurrentBodyTree(correspondence, body, scratch));
      const core::SurfacePoint nearest = tree->Closest(
          Eigen::Vector3d(gv[0], gv[1], gv[2]), std::numeric_limits<double>::infinity());
      if (nearest.found) {
        const bool clear = nearest.signed_distance >= offset;
        const Eigen::Vector4f out(static_cast<float>(nearest.normal.x()),
                                  static_cast<float>(nearest.normal.y()),
                                  static_cast<float>(nearest.normal.z()), 0);
        // A surface facing away from the anchor's side lies between the vertex and the
        // plane: the vertex is cleared against it, not pushed on through the body.
        if (nearest.normal.dot(Eigen::Vector3d(normal[0], normal[1], normal[2])) < 0) {
          if (!clear) push(out, static_cast<float>(offset - nearest.signed_distance));
          continue;
        }
        // Nothing collides: the plane's push is only the anchor's pull back to its side.
        if (clear) {
          push(along_anchor, static_cast<float>(kDeepPush));
          continue;
        }
      }
    }
    push(along_anchor, offset - scaled / length);
  }
  Eigen::VectorXf& garment4 = scratch.garment4;
  const Eigen::Index guard_count = correspondence.guard_triangles.rows();
  if (guard_count > 0) {
    if (garment4.size() != 4 * vertex_count) garment4.setZero(4 * vertex_count);
    for (Eigen::Index v = 0; v < vertex_count; ++v) {
      garment4.segment<3>(4 * v) = Eigen::Map<const Eigen::Vector3f>(positions + 3 * v);
    }
  }
  const auto garment_point4 = [&](int32_t i) {
    return LoadF4(garment4.data() + 4 * static_cast<Eigen::Index>(i));
  };
  for (Eigen::Index guard = 0; guard < guard_count; ++guard) {
    const F4 p = point4(correspondence.guard_body[guard]);
    const int32_t* corners = &correspondence.guard_triangles(guard, 0);
    const F4 a = garment_point4(corners[0]);
    const F4 ab = garment_point4(corners[1]) - a;
    const F4 ac = garment_point4(corners[2]) - a;
    const F4 cross = Cross(ab, ac);
    const float area2 = Dot(cross, cross);
    if (!(area2 > 0)) continue;
    // The height of the triangle's plane above the point, times |cross|: a guard that lies
    // clear is passed over without a root or a division.
    const F4 ap = p - a;
    const float scaled = -Dot(cross, ap);
    const float limit = scaled >= 0 ? offset : kGuardDepth;
    if (!(scaled * scaled < limit * limit * area2)) continue;
    const float length = std::sqrt(area2);
    // Barycentric coordinates of the point's projection onto the plane.
    const float wb = Dot(Cross(ap, ac), cross) / area2;
    const float wc = Dot(Cross(ab, ap), cross) / area2;
    const float wa = 1 - wb - wc;
    if (std::min({wa, wb, wc}) < -kGuardSlack) continue;
    Eigen::Vector3f w(std::max(wa, 0.0f), std::max(wb, 0.0f), std::max(wc, 0.0f));
    w /= w.sum();
    const F4 unit = cross / length;
    requests.push_back({{corners[0], corners[1], corners[2]}, {w[0], w[1], w[2]},
                        Eigen::Vector4f(unit[0], unit[1], unit[2], 0), offset - scaled / length});
  }
  if (requests.empty()) return 0;

  // The requests make a displacement field over the garment (zero between fits), each pushed
  // vertex listed once.
  Eigen::VectorXf& displacement = scratch.displacement;
  if (displacement.size() != 4 * vertex_count) displacement.setZero(4 * vertex_count);
  std::vector<uint8_t>& marked = scratch.marked;
  marked.resize(static_cast<size_t>(vertex_count), 0);
  std::vector<int32_t>& pushed = scratch.pushed;
  pushed.clear();
  pushed.reserve(static_cast<size_t>(vertex_count));
  for (const ClearanceRequest& r : requests) {
    Apply(r, displacement.data());
    for (int i = 0; i < 3; ++i) {
      if (r.weights[i] == 0 || marked[r.vertices[i]]) continue;
      marked[r.vertices[i]] = 1;
      pushed.push_back(r.vertices[i]);
    }
  }
  for (const int32_t v : pushed) marked[v] = 0;
  // Each pushed vertex keeps at least its push along its direction through the smoothing.
  std::vector<Eigen::Vector4f, Eigen::aligned_allocator<Eigen::Vector4f>>& held = scratch.held;
  std::vector<float>& held_squared = scratch.held_squared;
  held.reserve(static_cast<size_t>(vertex_count));
  held_squared.reserve(static_cast<size_t>(vertex_count));
  held.resize(pushed.size());
  held_squared.resize(pushed.size());
  for (size_t i = 0; i < pushed.size(); ++i) {
    held[i] = Point4(displacement.data(), pushed[i]);
    held_squared[i] = held[i].squaredNorm();
  }
  // Jacobi rounds over the whole garment: a push spreads one ring of neighbours per round, and
  // the cost is fixed, every vertex and edge once per round. (Gauss-Seidel sweeps over only
  // the vertices a push had reached cost 2.2 times as much per round on male_casualsuit01's
  // 8.4k vertices: finding the rings, and each vertex waiting for its neighbour's new value.)
  Eigen::VectorXf& next = scratch.displacement_next;
  next.resize(4 * vertex_count);
  for (int iteration = 0; iteration < correspondence.smoothing_iterations; ++iteration) {
    AverageOverNeighbors(correspondence, displacement.data(), next.data());
    displacement.swap(next);
    float* field = displacement.data();
    for (size_t i = 0; i < pushed.size(); ++i) {
      // d . h < |h|^2: d's length along h falls short of h's, and is topped up along h.
      auto d = Point4(field, pushed[i]);
      const float along = d.dot(held[i]);
      if (along < held_squared[i]) d += ((held_squared[i] - along) / held_squared[i]) * held[i];
    }
  }
  float* field = displacement.data();
  // Averaging may leave a triangle's request a little short where pushes of several corners
  // met; one more pass meets each exactly.
  if (correspondence.smoothing_iterations > 0) {
    for (const ClearanceRequest& r : requests) Apply(r, field);
  }
  int64_t moved = 0;
  for (Eigen::Index v = 0; v < vertex_count; ++v) {
    auto d = Point4(field, static_cast<int32_t>(v));
    if (d.isZero(0)) continue;
    Eigen::Map<Eigen::Vector3f>(positions + 3 * v) += d.head<3>();
    ++moved;
    d.setZero();
  }
  return moved;
}

}  // namespace fitbase::clothing
