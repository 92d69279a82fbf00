#include "proto/clothing_basis_codec.h"

#include <algorithm>
#include <cstdint>

#include "absl/strings/str_cat.h"
#include "core/kernel_ridge.h"
#include "core/mesh.h"
#include "core/status_macros.h"
#include "proto/garment_codec.h"
#include "proto/mesh_codec.h"

namespace fitbase::proto {

// Kernel shapes are stored by their number.
static_assert(static_cast<int>(core::KernelShape::kGaussian) == v1::KernelCorrection::GAUSSIAN);
static_assert(static_cast<int>(core::KernelShape::kMatern32) == v1::KernelCorrection::MATERN_3_2);
namespace {

// The garment's faces as the basis stores them, positioned at the clothing mean.
absl::StatusOr<v1::Mesh> FacesAtMean(const v1::ClothingBasis& message) {
  if (message.faces().vertex_count() != message.vertex_count() ||
      message.mean_size() != 3 * static_cast<int64_t>(message.vertex_count())) {
    return absl::InvalidArgumentError(absl::StrCat("clothing basis ", message.id(), " has faces for ",
                                                   message.faces().vertex_count(),
                                                   " vertices; its model has ",
                                                   message.vertex_count()));
  }
  v1::Mesh mesh = message.faces();
  *mesh.mutable_positions() = message.mean();
  return mesh;
}

// A stored index. Values past INT32_MAX become INT32_MAX, which the correspondence's
// validation then refuses as out of range.
int32_t ClampedIndex(uint32_t index) {
  return static_cast<int32_t>(std::min<uint32_t>(index, INT32_MAX));
}

// Stored indices (a multiple of 3 of them, checked by the caller) as rows of three.
core::Triangles IndexRows(const google::protobuf::RepeatedField<uint32_t>& indices) {
  core::Triangles rows(indices.size() / 3, 3);
  for (int i = 0; i < indices.size(); ++i) rows(i / 3, i % 3) = ClampedIndex(indices[i]);
  return rows;
}

}  // namespace

void ClothingModelToProto(const clothing::ClothingModel& model, v1::ClothingBasis* message) {
  message->set_method(clothing::ClothingMethodName(model.method));
  message->set_vertex_count(static_cast<uint32_t>(model.vertex_count()));
  message->set_component_count(static_cast<uint32_t>(model.component_count));
  const auto mean = model.mean();
  message->mutable_mean()->Assign(mean.begin(), mean.end());
  const auto terms = model.terms().reshaped();
  message->mutable_terms()->Assign(terms.begin(), terms.end());
  message->mutable_term_component()->Assign(model.term_component.begin(),
                                            model.term_component.end());
  message->mutable_term_power()->Assign(model.term_power.begin(), model.term_power.end());
  if (model.method != clothing::ClothingMethod::kKernel) {
    message->clear_kernel();
    return;
  }
  const clothing::KernelCorrection& kernel = model.kernel;
  v1::KernelCorrection* out = message->mutable_kernel();
  out->set_shape(static_cast<v1::KernelCorrection::Shape>(kernel.shape));
  out->set_length_scale(kernel.length_scale);
  out->mutable_input_scale()->Assign(kernel.input_scale.begin(), kernel.input_scale.end());
  out->set_center_count(static_cast<uint32_t>(kernel.center_count()));
  const auto centers = kernel.centers.reshaped();
  out->mutable_centers()->Assign(centers.begin(), centers.end());
  out->set_output_count(static_cast<uint32_t>(kernel.output_count()));
  const auto coefficients = kernel.coefficients.reshaped();
  out->mutable_coefficients()->Assign(coefficients.begin(), coefficients.end());
  const auto outputs = model.kernel_outputs().reshaped();
  out->mutable_outputs()->Assign(outputs.begin(), outputs.end());
}

void BodyCorrespondenceToProto(const clothing::BodyCorrespondence& correspondence,
                               v1::BodyCorrespondence* message) {
  message->set_offset(correspondence.offset);
  message->set_anchors_per_vertex(static_cast<uint32_t>(correspondence.anchors_per_vertex));
  message->mutable_body_vertices()->Assign(correspondence.body_vertices.begin(),
                                           correspondence.body_vertices.end());
  message->mutable_body_mean()->Assign(correspondence.body_mean.begin(),
                                       correspondence.body_mean.end());
  const auto components = correspondence.body_components.reshaped();
  message->mutable_body_components()->Assign(components.begin(), components.end());
  const auto corners = correspondence.corners.reshaped<Eigen::RowMajor>();
  message->mutable_corners()->Assign(corners.begin(), corners.end());
  const auto barycentric = correspondence.barycentric.reshaped<Eigen::RowMajor>();
  message->mutable_barycentric()->Assign(barycentric.begin(), barycentric.end());
  message->mutable_guard_body()->Assign(correspondence.guard_body.begin(),
                                        correspondence.guard_body.end());
  const auto guards = correspondence.guard_triangles.reshaped<Eigen::RowMajor>();
  message->mutable_guard_triangles()->Assign(guards.begin(), guards.end());
  message->set_smoothing_iterations(static_cast<uint32_t>(correspondence.smoothing_iterations));
  const auto body_triangles = correspondence.body_triangles.reshaped<Eigen::RowMajor>();
  message->mutable_body_triangles()->Assign(body_triangles.begin(), body_triangles.end());
}

absl::StatusOr<clothing::ClothingModel> ClothingModelFromProto(const v1::ClothingBasis& message) {
  ASSIGN_OR_RETURN(clothing::ClothingMethod method,
                   clothing::ParseClothingMethod(message.method()));
  const int64_t d = 3 * static_cast<int64_t>(message.vertex_count());
  const int64_t t = message.term_component_size();
  if (message.mean_size() != d || message.terms_size() != d * t ||
      message.term_power_size() != t) {
    return absl::InvalidArgumentError(absl::StrCat(
        "clothing basis ", message.id(), " is inconsistent: ", message.vertex_count(),
        " vertices and ", t, " terms need ", d, " mean and ", d * t, " term values, found ",
        message.mean_size(), " and ", message.terms_size()));
  }
  const v1::KernelCorrection& kernel = message.kernel();
  const int64_t n = message.component_count();
  const int64_t m = kernel.center_count();
  const int64_t c = kernel.output_count();
  // Bounds before any product of counts, so a hostile file cannot overflow the checks.
  const int64_t scales = method == clothing::ClothingMethod::kKernel ? n : 0;
  if (n > (1 << 16) || m > (1 << 20) || c > (1 << 16) || kernel.input_scale_size() != scales ||
      kernel.centers_size() != n * m || kernel.coefficients_size() != c * m ||
      kernel.outputs_size() != c * d) {
    return absl::InvalidArgumentError(absl::StrCat(
        "clothing basis ", message.id(), " has an inconsistent kernel correction: ", m,
        " centers of ", n, " weights and ", c, " outputs of ", d, " values need ", n * m, ", ",
        c * m, " and ", c * d, ", found ", kernel.centers_size(), ", ",
        kernel.coefficients_size(), " and ", kernel.outputs_size()));
  }
  clothing::ClothingModel model;
  model.method = method;
  model.component_count = static_cast<int>(n);
  model.basis.resize(d, 1 + t + c);
  model.basis.col(0) = Eigen::Map<const Eigen::VectorXf>(message.mean().data(), d);
  model.basis.middleCols(1, t) = Eigen::Map<const Eigen::MatrixXf>(message.terms().data(), d, t);
  model.basis.rightCols(c) = Eigen::Map<const Eigen::MatrixXf>(kernel.outputs().data(), d, c);
  if (method == clothing::ClothingMethod::kKernel) {
    if (!v1::KernelCorrection::Shape_IsValid(kernel.shape())) {
      return absl::InvalidArgumentError(absl::StrCat("clothing basis ", message.id(),
                                                     " has a kernel of unknown shape ",
                                                     static_cast<int>(kernel.shape())));
    }
    model.kernel.shape = static_cast<core::KernelShape>(kernel.shape());
    model.kernel.length_scale = kernel.length_scale();
    model.kernel.input_scale = Eigen::Map<const Eigen::VectorXf>(kernel.input_scale().data(), n);
    model.kernel.centers = Eigen::Map<const Eigen::MatrixXf>(kernel.centers().data(), n, m);
    model.kernel.coefficients =
        Eigen::Map<const Eigen::MatrixXf>(kernel.coefficients().data(), c, m);
  }
  for (int64_t i = 0; i < t; ++i) {
    model.term_component.push_back(static_cast<int32_t>(message.term_component(i)));
    model.term_power.push_back(static_cast<int32_t>(message.term_power(i)));
  }
  RETURN_IF_ERROR(clothing::ValidateClothingModel(model));
  return model;
}

absl::StatusOr<clothing::BodyCorrespondence> BodyCorrespondenceFromProto(
    const v1::ClothingBasis& message) {
  const v1::BodyCorrespondence& c = message.correspondence();
  const int64_t v = message.vertex_count();
  const int64_t k = c.anchors_per_vertex();
  const int64_t u = c.body_vertices_size();
  const int64_t n = message.component_count();
  const int64_t g = c.guard_body_size();
  if (k < 1 || k > 64 || c.corners_size() != 3 * v * k || c.barycentric_size() != 3 * v * k ||
      c.body_mean_size() != 3 * u || c.body_components_size() != 3 * u * n ||
      c.guard_triangles_size() != 3 * g || c.body_triangles_size() % 3 != 0 ||
      c.smoothing_iterations() > clothing::kMaxSmoothingIterations) {
    return absl::InvalidArgumentError(absl::StrCat(
        "clothing basis ", message.id(), " has an inconsistent body correspondence (", v,
        " garment vertices, ", u, " body vertices, ", n, " components)"));
  }
  clothing::BodyCorrespondence result;
  result.offset = c.offset();
  result.anchors_per_vertex = static_cast<int>(k);
  result.body_vertices.assign(c.body_vertices().begin(), c.body_vertices().end());
  result.body_mean = Eigen::Map<const Eigen::VectorXf>(c.body_mean().data(), 3 * u);
  result.body_components = Eigen::Map<const Eigen::MatrixXf>(c.body_components().data(), 3 * u, n);
  result.corners = IndexRows(c.corners());
  result.barycentric =
      Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>>(
          c.barycentric().data(), v * k, 3);
  for (uint32_t b : c.guard_body()) result.guard_body.push_back(ClampedIndex(b));
  result.guard_triangles = IndexRows(c.guard_triangles());
  result.body_triangles = IndexRows(c.body_triangles());
  result.smoothing_iterations = static_cast<int>(c.smoothing_iterations());
  if (result.smoothing_iterations > 0) {
    // The smoothing runs over the garment's edges, which its faces give.
    ASSIGN_OR_RETURN(const v1::Mesh faces, FacesAtMean(message));
    ASSIGN_OR_RETURN(const core::Mesh mesh, MeshFromProto(faces));
    RETURN_IF_ERROR(clothing::SetGarmentNeighbors(core::Triangulate(mesh.faces), result));
  }
  RETURN_IF_ERROR(clothing::ValidateBodyCorrespondence(result, v, static_cast<int>(n)));
  return result;
}

absl::StatusOr<clothing::ClothingFitter> ClothingFitterFromProto(const v1::ClothingBasis& message) {
  ASSIGN_OR_RETURN(clothing::ClothingModel model, ClothingModelFromProto(message));
  ASSIGN_OR_RETURN(clothing::BodyCorrespondence correspondence,
                   BodyCorrespondenceFromProto(message));
  return clothing::ClothingFitter::Create(std::move(model), std::move(correspondence));
}

absl::StatusOr<core::GarmentMesh> GarmentMeshFromClothingBasis(const v1::ClothingBasis& message) {
  ASSIGN_OR_RETURN(const v1::Mesh mesh, FacesAtMean(message));
  return GarmentMeshFromProto(mesh, message.texcoords(), message.face_texcoord_indices());
}

}  // namespace fitbase::proto
