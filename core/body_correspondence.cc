#include "core/body_correspondence.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "Eigen/Geometry"
#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "core/triangle_bvh.h"

namespace fitbase::core {

namespace {

// A triangle a garment vertex was closest to, how often, and where first.
struct AnchorCount {
  int32_t triangle;
  int count;
  int first_example;
  Eigen::Vector3f barycentric;
};

}  // namespace

absl::StatusOr<BodyCorrespondence> BuildBodyCorrespondence(
    const std::vector<CorrespondenceExample>& examples, const PcaBasis& avatar,
    const Triangles& body_triangles, double offset, int anchors_per_vertex) {
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
  const Positions mean = Eigen::Map<const Positions>(avatar.mean.data(), avatar.mean.size() / 3, 3);
  ASSIGN_OR_RETURN(TriangleBvh bvh, TriangleBvh::Build(mean, body_triangles));

  std::vector<std::vector<AnchorCount>> seen(vertex_count);
  for (size_t e = 0; e < examples.size(); ++e) {
    const Eigen::VectorXd body = ReconstructFromWeights(avatar, examples[e].weights);
    bvh.Refit(Eigen::Map<const Positions>(body.data(), body.size() / 3, 3));
    for (Eigen::Index v = 0; v < vertex_count; ++v) {
      const SurfacePoint closest = bvh.Closest(examples[e].garment->row(v).transpose(),
                                               std::numeric_limits<double>::infinity());
      if (!closest.found) return absl::InternalError("no closest body point for a garment vertex");
      std::vector<AnchorCount>& anchors = seen[v];
      auto it = std::find_if(anchors.begin(), anchors.end(), [&](const AnchorCount& a) {
        return a.triangle == closest.triangle;
      });
      if (it != anchors.end()) {
        ++it->count;
      } else {
        anchors.push_back({closest.triangle, 1, static_cast<int>(e), closest.barycentric.cast<float>()});
      }
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
  result.corners.resize(rows, 3);
  for (Eigen::Index r = 0; r < rows; ++r) {
    for (int c = 0; c < 3; ++c) {
      result.corners(r, c) = static_cast<int32_t>(
          std::lower_bound(result.body_vertices.begin(), result.body_vertices.end(),
                           body_triangles(triangles[r], c)) -
          result.body_vertices.begin());
    }
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
  return absl::OkStatus();
}

int64_t PushOutOfBody(const BodyCorrespondence& correspondence, const Eigen::VectorXf& weights,
                      Eigen::VectorXf& body, float* positions) {
  body = correspondence.body_mean;
  body.noalias() += correspondence.body_components * weights;
  const float offset = static_cast<float>(correspondence.offset);
  const int k = correspondence.anchors_per_vertex;
  int64_t moved = 0;
  for (Eigen::Index v = 0; v < correspondence.vertex_count(); ++v) {
    Eigen::Map<Eigen::Vector3f> g(positions + 3 * v);
    Eigen::Vector3f point = Eigen::Vector3f::Zero();
    Eigen::Index nearest = -1;
    float best = std::numeric_limits<float>::infinity();
    for (Eigen::Index r = v * k; r < (v + 1) * k; ++r) {
      const Eigen::Vector3f anchor =
          correspondence.barycentric(r, 0) * body.segment<3>(3 * correspondence.corners(r, 0)) +
          correspondence.barycentric(r, 1) * body.segment<3>(3 * correspondence.corners(r, 1)) +
          correspondence.barycentric(r, 2) * body.segment<3>(3 * correspondence.corners(r, 2));
      const float distance = (g - anchor).squaredNorm();
      if (distance < best) {
        best = distance;
        point = anchor;
        nearest = r;
      }
    }
    if (nearest < 0) continue;
    // Only the nearest anchor's plane is needed: its normal is computed once, not per anchor.
    const Eigen::Vector3f a = body.segment<3>(3 * correspondence.corners(nearest, 0));
    const Eigen::Vector3f b = body.segment<3>(3 * correspondence.corners(nearest, 1));
    const Eigen::Vector3f c = body.segment<3>(3 * correspondence.corners(nearest, 2));
    Eigen::Vector3f normal = (b - a).cross(c - a);
    const float length = normal.norm();
    if (!(length > 0)) continue;
    normal /= length;
    const float distance = (g - point).dot(normal);
    if (distance < offset) {
      g += (offset - distance) * normal;
      ++moved;
    }
  }
  return moved;
}

}  // namespace fitbase::core
