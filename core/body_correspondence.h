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

// The collision clean-up of a fast fit: each garment vertex remembers the body triangle it was
// closest to on the mean drape, and that triangle's corners as a linear model in the avatar
// weights. At fit time the customer's triangle is rebuilt from the weights and the vertex is
// pushed out along its normal when it lies closer than `offset`: constant time per vertex,
// no BVH.
struct BodyCorrespondence {
  double offset = 0;                  // m.
  std::vector<int32_t> body_vertices;  // U avatar vertices the triangles use, ascending.
  Eigen::VectorXf body_mean;           // 3U, m.
  Eigen::MatrixXf body_components;     // 3U x N.
  // Per garment vertex (V rows): the corners as rows of body_vertices, and the barycentric
  // coordinates of its closest point.
  Eigen::Matrix<int32_t, Eigen::Dynamic, 3, Eigen::RowMajor> corners;
  Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor> barycentric;
  int64_t vertex_count() const { return corners.rows(); }
  int component_count() const { return static_cast<int>(body_components.cols()); }
};

// garment: the mean drape, V x 3 (m); avatar: the basis whose mean it sits on (D = 3 x body
// vertices); body_triangles: the avatar topology, counter-clockwise from outside.
// offset: m, > 0. InvalidArgument for non-finite or mismatched input.
absl::StatusOr<BodyCorrespondence> BuildBodyCorrespondence(const Positions& garment,
                                                           const PcaBasis& avatar,
                                                           const Triangles& body_triangles,
                                                           double offset);

// Sizes, indices and values agree and are finite.
absl::Status ValidateBodyCorrespondence(const BodyCorrespondence& correspondence,
                                        int64_t garment_vertex_count, int component_count);

// positions: 3V floats (m), xyz interleaved, moved in place; weights: N, checked by the
// caller; body: scratch of 3U floats. Returns how many vertices moved.
int64_t PushOutOfBody(const BodyCorrespondence& correspondence, const Eigen::VectorXf& weights,
                      Eigen::VectorXf& body, float* positions);

}  // namespace fitbase::core

#endif  // FITBASE_CORE_BODY_CORRESPONDENCE_H_
