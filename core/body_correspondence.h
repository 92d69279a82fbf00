#ifndef FITBASE_CORE_BODY_CORRESPONDENCE_H_
#define FITBASE_CORE_BODY_CORRESPONDENCE_H_

#include <cstdint>
#include <vector>

#include "Eigen/Core"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "core/mesh.h"
#include "core/pca_basis.h"

namespace fitbase::core {

// The collision clean-up of a fast fit. Each garment vertex keeps up to K anchors: the body
// surface points it was closest to in the example drapes (triangle and barycentric
// coordinates), with the triangles' corners as a linear model in the avatar weights. At fit
// time the customer's triangles are rebuilt from the weights, the anchor nearest the fitted
// vertex is taken, and the vertex is pushed out along that triangle's normal when it lies
// closer than `offset`: constant time per vertex, no BVH. Anchors from several examples follow
// a vertex that slides from one body part's surface to another's as the body changes shape.
struct BodyCorrespondence {
  double offset = 0;                   // m.
  int anchors_per_vertex = 1;          // K.
  std::vector<int32_t> body_vertices;  // U avatar vertices the triangles use, ascending.
  Eigen::VectorXf body_mean;           // 3U, m.
  Eigen::MatrixXf body_components;     // 3U x N.
  // Rows v * K .. v * K + K - 1 are garment vertex v's anchors: the triangle's corners as rows
  // of body_vertices, and the barycentric coordinates of the anchor in it.
  Eigen::Matrix<int32_t, Eigen::Dynamic, 3, Eigen::RowMajor> corners;
  Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor> barycentric;
  int64_t vertex_count() const { return corners.rows() / anchors_per_vertex; }
  int component_count() const { return static_cast<int>(body_components.cols()); }
};

// A configuration the garment was seen in: a drape (V x 3, m) and its body's avatar weights.
struct CorrespondenceExample {
  const Positions* garment = nullptr;
  Eigen::VectorXd weights;  // N, m.
};

// examples: the mean drape first (weights 0), then any others; avatar: the basis the weights
// refer to (D = 3 x body vertices); body_triangles: the avatar topology, counter-clockwise
// from outside; offset: m, > 0; anchors_per_vertex: K >= 1, the most frequent closest
// triangles over the examples (ties: the earlier example), padded by repeating the first.
// InvalidArgument for non-finite or mismatched input.
absl::StatusOr<BodyCorrespondence> BuildBodyCorrespondence(
    const std::vector<CorrespondenceExample>& examples, const PcaBasis& avatar,
    const Triangles& body_triangles, double offset, int anchors_per_vertex);

// Sizes, indices and values agree and are finite.
absl::Status ValidateBodyCorrespondence(const BodyCorrespondence& correspondence,
                                        int64_t garment_vertex_count, int component_count);

// positions: 3V floats (m), xyz interleaved, moved in place; weights: N, checked by the
// caller; body: scratch of 3U floats. Returns how many vertices moved.
int64_t PushOutOfBody(const BodyCorrespondence& correspondence, const Eigen::VectorXf& weights,
                      Eigen::VectorXf& body, float* positions);

}  // namespace fitbase::core

#endif  // FITBASE_CORE_BODY_CORRESPONDENCE_H_
