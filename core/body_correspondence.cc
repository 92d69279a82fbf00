#include "core/body_correspondence.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "Eigen/Geometry"
#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "core/triangle_bvh.h"

namespace fitbase::core {

absl::StatusOr<BodyCorrespondence> BuildBodyCorrespondence(const Positions& garment,
                                                           const PcaBasis& avatar,
                                                           const Triangles& body_triangles,
                                                           double offset) {
  if (!std::isfinite(offset) || offset <= 0) {
    return absl::InvalidArgumentError(absl::StrCat("clean-up offset must be > 0 m, got ", offset));
  }
  if (garment.rows() == 0 || !garment.allFinite()) {
    return absl::InvalidArgumentError("mean drape is empty or not finite");
  }
  const Positions body = Eigen::Map<const Positions>(avatar.mean.data(), avatar.mean.size() / 3, 3);
  ASSIGN_OR_RETURN(TriangleBvh bvh, TriangleBvh::Build(body, body_triangles));

  std::vector<Eigen::Vector3i> triangles(garment.rows());
  BodyCorrespondence result;
  result.offset = offset;
  result.barycentric.resize(garment.rows(), 3);
  for (Eigen::Index v = 0; v < garment.rows(); ++v) {
    const SurfacePoint closest =
        bvh.Closest(garment.row(v).transpose(), std::numeric_limits<double>::infinity());
    if (!closest.found) return absl::InternalError("no closest body point for a garment vertex");
    triangles[v] = body_triangles.row(closest.triangle).transpose();
    result.barycentric.row(v) = closest.barycentric.cast<float>().transpose();
    for (int c = 0; c < 3; ++c) result.body_vertices.push_back(triangles[v](c));
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
  result.corners.resize(garment.rows(), 3);
  for (Eigen::Index v = 0; v < garment.rows(); ++v) {
    for (int c = 0; c < 3; ++c) {
      result.corners(v, c) = static_cast<int32_t>(
          std::lower_bound(result.body_vertices.begin(), result.body_vertices.end(),
                           triangles[v](c)) -
          result.body_vertices.begin());
    }
  }
  return result;
}

absl::Status ValidateBodyCorrespondence(const BodyCorrespondence& correspondence,
                                        int64_t garment_vertex_count, int component_count) {
  const Eigen::Index u = static_cast<Eigen::Index>(correspondence.body_vertices.size());
  if (correspondence.corners.rows() != garment_vertex_count ||
      correspondence.barycentric.rows() != garment_vertex_count) {
    return absl::InvalidArgumentError(
        absl::StrCat("body correspondence covers ", correspondence.corners.rows(),
                     " vertices; the garment has ", garment_vertex_count));
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
  int64_t moved = 0;
  for (Eigen::Index v = 0; v < correspondence.corners.rows(); ++v) {
    const Eigen::Vector3f a = body.segment<3>(3 * correspondence.corners(v, 0));
    const Eigen::Vector3f b = body.segment<3>(3 * correspondence.corners(v, 1));
    const Eigen::Vector3f c = body.segment<3>(3 * correspondence.corners(v, 2));
    Eigen::Vector3f normal = (b - a).cross(c - a);
    const float length = normal.norm();
    if (!(length > 0)) continue;
    normal /= length;
    const Eigen::Vector3f point = correspondence.barycentric(v, 0) * a +
                                  correspondence.barycentric(v, 1) * b +
                                  correspondence.barycentric(v, 2) * c;
    Eigen::Map<Eigen::Vector3f> g(positions + 3 * v);
    const float distance = (g - point).dot(normal);
    if (distance < offset) {
      g += (offset - distance) * normal;
      ++moved;
    }
  }
  return moved;
}

}  // namespace fitbase::core
