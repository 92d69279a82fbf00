#ifndef FITBASE_CORE_TRIANGLE_BVH_H_
#define FITBASE_CORE_TRIANGLE_BVH_H_

#include <array>
#include <cstdint>
#include <vector>

#include "Eigen/Core"
#include "absl/status/statusor.h"
#include "core/mesh.h"

namespace fitbase::core {

// The closest point of a triangle mesh to a query point.
struct SurfacePoint {
  bool found = false;            // False when nothing lies within the query's max distance.
  int32_t triangle = -1;         // Row of the triangle in the mesh's Triangles.
  Eigen::Vector3d barycentric;   // Of `point` in that triangle (sums to 1).
  Eigen::Vector3d point;         // Closest point on the surface, meters.
  Eigen::Vector3d normal;        // Unit angle-weighted pseudo-normal of the closest feature.
  double signed_distance = 0.0;  // |query - point|, negative inside (pseudo-normal side), m.
};

// Exact closest-point and signed-distance queries against a triangle mesh whose vertices move
// while its topology stays (a body during a drape). An AABB tree built once by median splits,
// refitted bottom-up when the vertices move; signs come from angle-weighted pseudo-normals of
// the closest face, edge or vertex (Baerentzen & Aanaes 2005), which is exact for a closed,
// consistently oriented mesh and locally right near open boundaries.
class TriangleBvh {
 public:
  // positions: V x 3 (m); triangles: T x 3 indices into positions, T >= 1, counter-clockwise
  // seen from outside. Errors: empty input, out-of-range index, non-finite position.
  static absl::StatusOr<TriangleBvh> Build(const Positions& positions, const Triangles& triangles);

  // Same vertex count as at Build (a caller's bug otherwise, checked only by assert); updates
  // the boxes in O(V + T). Pseudo-normals are not stored: Closest derives the one it needs
  // from the current positions, because angle-weighting every vertex (an atan2 per triangle
  // corner, about 0.8 ms on the MakeHuman body) would cost several times what the boxes do,
  // while a substep's queries touch only the few features they land on.
  void Refit(const Positions& positions);

  // The closest surface point to `query` within `max_distance` (m), exact. Among triangles at
  // the same computed distance the lowest row wins, so the result depends on the positions and
  // triangles only, not on the tree: a refitted tree answers bit for bit like a fresh Build.
  // A non-finite query or a negative or NaN max_distance finds nothing.
  // `hint`: a triangle row likely to be nearest, such as the answer for a nearby query (a
  // garment vertex's at the previous iterate), or -1. It is measured first, so that its
  // distance prunes the tree from the start; the answer is the same, bit for bit, with any
  // hint (an out-of-range one is ignored).
  SurfacePoint Closest(const Eigen::Vector3d& query, double max_distance,
                       int32_t hint = -1) const;

  const Positions& positions() const { return positions_; }
  const Triangles& triangles() const { return triangles_; }

 private:
  // A subtree: the node `index` when count == 0, else the leaf of slots [index, index + count).
  struct Child {
    int32_t index = 0;
    int32_t count = 0;
  };

  // An inner node holds its two children's boxes axis by axis, so that one pass of two-lane
  // arithmetic measures both. Nodes are stored in depth-first order: children after parents.
  struct Node {
    Eigen::Array2d lo[3];
    Eigen::Array2d hi[3];
    Child child[2];
  };

  // A triangle's corners copied in slot order, so that a leaf's triangles are contiguous.
  struct Corners {
    Eigen::Vector3d a;
    Eigen::Vector3d b;
    Eigen::Vector3d c;
  };

  TriangleBvh() = default;

  // Builds the subtree over slots [begin, end) of order_, splitting at the median centroid
  // along the longest axis of their bounds, and returns it.
  Child BuildSubtree(int32_t begin, int32_t end, const std::vector<Eigen::Vector3d>& centroids);
  // Fills edge and vertex incidence, which pseudo-normals need and the topology fixes.
  void BuildAdjacency(Eigen::Index vertex_count);

  // Pseudo-normal of triangle t's side k (corners k, k + 1) or its corner k.
  Eigen::Vector3d EdgeNormal(int32_t t, int k) const;
  Eigen::Vector3d VertexNormal(int32_t t, int k) const;

  Positions positions_;
  Triangles triangles_;
  Child root_;
  std::vector<Node> nodes_;
  // The largest coordinate magnitude, which bounds the rounding error of distances.
  double coordinate_bound_ = 0.0;
  std::vector<int32_t> order_;                          // Triangle of each slot.
  std::vector<int32_t> slot_of_;                        // Slot of each triangle.
  std::vector<Corners> corners_;                        // Corners of each slot's triangle.
  std::vector<std::array<int32_t, 3>> triangle_edges_;  // Edge id of each triangle side.
  // Edge e's triangles are edge_triangles_[edge_offsets_[e] .. edge_offsets_[e + 1]).
  std::vector<int32_t> edge_offsets_;
  std::vector<int32_t> edge_triangles_;
  // Vertex v's corners (3 * triangle + corner) are
  // vertex_corners_[vertex_offsets_[v] .. vertex_offsets_[v + 1]).
  std::vector<int32_t> vertex_offsets_;
  std::vector<int32_t> vertex_corners_;
};

}  // namespace fitbase::core

#endif  // FITBASE_CORE_TRIANGLE_BVH_H_
