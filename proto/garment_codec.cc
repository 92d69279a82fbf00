#include "proto/garment_codec.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "proto/mesh_codec.h"

namespace fitbase::proto {

v1::MhcloBinding MhcloBindingToProto(const core::MhcloBinding& b) {
  v1::MhcloBinding m;
  const Eigen::Index n = b.vertex_count();
  for (Eigen::Index v = 0; v < n; ++v) {
    for (int k = 0; k < 3; ++k) {
      m.add_reference_vertices(static_cast<uint32_t>(b.reference_vertices(v, k)));
      m.add_weights(b.weights(v, k));
      m.add_offsets(b.offsets(v, k));
    }
  }
  for (const core::MhcloBinding::AxisScale& s : b.scales) {
    m.add_scale_vertices(static_cast<uint32_t>(s.i));
    m.add_scale_vertices(static_cast<uint32_t>(s.j));
    m.add_scale_reference_distances(s.reference_distance);
  }
  return m;
}

absl::StatusOr<core::MhcloBinding> MhcloBindingFromProto(const v1::MhcloBinding& m,
                                                         int64_t vertex_count,
                                                         int64_t reference_vertex_count) {
  if (m.reference_vertices_size() != 3 * vertex_count || m.weights_size() != 3 * vertex_count ||
      m.offsets_size() != 3 * vertex_count) {
    return absl::InvalidArgumentError(absl::StrCat(
        "garment binding has ", m.reference_vertices_size() / 3, " vertices; the garment has ",
        vertex_count));
  }
  if (m.scale_vertices_size() != 6 || m.scale_reference_distances_size() != 3) {
    return absl::InvalidArgumentError("garment binding needs x, y and z scales");
  }
  auto out_of_range = [&](uint32_t index) { return index >= reference_vertex_count; };
  if (std::any_of(m.reference_vertices().begin(), m.reference_vertices().end(), out_of_range) ||
      std::any_of(m.scale_vertices().begin(), m.scale_vertices().end(), out_of_range)) {
    return absl::InvalidArgumentError(absl::StrCat(
        "garment binding refers to a vertex beyond the reference mesh's ", reference_vertex_count));
  }
  core::MhcloBinding b;
  b.reference_vertices.resize(vertex_count, 3);
  b.weights.resize(vertex_count, 3);
  b.offsets.resize(vertex_count, 3);
  for (int i = 0; i < 3 * vertex_count; ++i) {
    b.reference_vertices.data()[i] = static_cast<int32_t>(m.reference_vertices(i));
    b.weights.data()[i] = m.weights(i);
    b.offsets.data()[i] = m.offsets(i);
  }
  for (int a = 0; a < 3; ++a) {
    b.scales[a] = {static_cast<int32_t>(m.scale_vertices(2 * a)),
                   static_cast<int32_t>(m.scale_vertices(2 * a + 1)),
                   m.scale_reference_distances(a)};
    if (!(b.scales[a].reference_distance > 0)) {
      return absl::InvalidArgumentError("garment binding has a non-positive scale distance");
    }
  }
  if (!b.weights.allFinite() || !b.offsets.allFinite()) {
    return absl::InvalidArgumentError("garment binding has non-finite values");
  }
  return b;
}

absl::StatusOr<core::GarmentMesh> GarmentMeshFromProto(
    const v1::Mesh& mesh, const google::protobuf::RepeatedField<float>& texcoords,
    const google::protobuf::RepeatedField<int32_t>& face_texcoord_indices) {
  core::GarmentMesh g;
  ASSIGN_OR_RETURN(g.mesh, MeshFromProto(mesh));
  const int64_t texcoord_count = texcoords.size() / 2;
  if (texcoords.size() % 2 != 0) {
    return absl::InvalidArgumentError("garment texture coordinates come in pairs");
  }
  g.texcoords.resize(texcoord_count, 2);
  for (int i = 0; i < texcoords.size(); ++i) g.texcoords.data()[i] = texcoords[i];
  if (!face_texcoord_indices.empty()) {
    if (face_texcoord_indices.size() != static_cast<int>(g.mesh.faces.indices.size())) {
      return absl::InvalidArgumentError("garment has one texture index per face corner or none");
    }
    for (int32_t t : face_texcoord_indices) {
      if (t < -1 || t >= texcoord_count) {
        return absl::InvalidArgumentError(absl::StrCat("garment texture index ", t, " out of range"));
      }
    }
    g.face_texcoord_indices.assign(face_texcoord_indices.begin(), face_texcoord_indices.end());
  }
  return g;
}

absl::StatusOr<core::GarmentMesh> GarmentTemplateFromProto(const v1::Garment& garment) {
  return GarmentMeshFromProto(garment.template_mesh(), garment.texcoords(),
                              garment.face_texcoord_indices());
}

absl::StatusOr<core::Positions> LengthAxesFromProto(const v1::Garment& garment) {
  const int64_t n = garment.template_mesh().vertex_count();
  if (garment.length_axes_size() != 3 * n) {
    return absl::InvalidArgumentError(absl::StrCat("garment has ", garment.length_axes_size() / 3,
                                                   " length axes for ", n, " vertices"));
  }
  core::Positions axes(n, 3);
  for (int i = 0; i < 3 * n; ++i) axes.data()[i] = garment.length_axes(i);
  if (!axes.allFinite()) return absl::InvalidArgumentError("garment length axes are not finite");
  return axes;
}

absl::StatusOr<std::vector<body::BodyRegion>> RegionsFromProto(const v1::Garment& garment) {
  const int64_t n = garment.template_mesh().vertex_count();
  if (garment.vertex_regions_size() != n) {
    return absl::InvalidArgumentError(absl::StrCat("garment has ", garment.vertex_regions_size(),
                                                   " vertex regions for ", n, " vertices"));
  }
  std::vector<body::BodyRegion> regions;
  for (uint32_t r : garment.vertex_regions()) {
    if (r >= body::kBodyRegionCount) {
      return absl::InvalidArgumentError(absl::StrCat("garment vertex region ", r, " is unknown"));
    }
    regions.push_back(static_cast<body::BodyRegion>(r));
  }
  return regions;
}

}  // namespace fitbase::proto
