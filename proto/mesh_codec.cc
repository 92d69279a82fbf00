#include "proto/mesh_codec.h"

#include <cmath>

#include "absl/strings/str_cat.h"

namespace fitbase::proto {

v1::Mesh MeshToProto(const core::Mesh& mesh) {
  v1::Mesh message;
  message.set_topology_id(mesh.topology_id);
  message.set_vertex_count(static_cast<uint32_t>(mesh.vertex_count()));
  auto* positions = message.mutable_positions();
  positions->Reserve(static_cast<int>(mesh.positions.size()));
  for (Eigen::Index i = 0; i < mesh.positions.size(); ++i) {
    positions->AddAlreadyReserved(static_cast<float>(mesh.positions.data()[i]));
  }
  message.mutable_face_sizes()->Assign(mesh.faces.sizes.begin(), mesh.faces.sizes.end());
  message.mutable_face_indices()->Assign(mesh.faces.indices.begin(), mesh.faces.indices.end());
  return message;
}

absl::StatusOr<core::Mesh> MeshFromProto(const v1::Mesh& message) {
  const int64_t vertex_count = message.vertex_count();
  if (message.positions_size() != 3 * vertex_count) {
    return absl::InvalidArgumentError(absl::StrCat("mesh has ", message.positions_size(),
                                                   " position values for ", vertex_count,
                                                   " vertices; expected ", 3 * vertex_count));
  }
  core::Mesh mesh;
  mesh.topology_id = message.topology_id();
  mesh.positions.resize(vertex_count, 3);
  for (int i = 0; i < message.positions_size(); ++i) {
    const float value = message.positions(i);
    if (!std::isfinite(value)) {
      return absl::InvalidArgumentError(
          absl::StrCat("mesh vertex ", i / 3, " has a non-finite coordinate"));
    }
    mesh.positions.data()[i] = value;
  }
  int64_t corners = 0;
  for (uint32_t size : message.face_sizes()) {
    if (size < 3) return absl::InvalidArgumentError("mesh has a face with fewer than 3 corners");
    corners += size;
  }
  if (corners != message.face_indices_size()) {
    return absl::InvalidArgumentError(absl::StrCat("mesh face sizes add up to ", corners,
                                                   " corners but ", message.face_indices_size(),
                                                   " indices are given"));
  }
  for (uint32_t index : message.face_indices()) {
    if (index >= vertex_count) {
      return absl::InvalidArgumentError(
          absl::StrCat("mesh face index ", index, " is not below vertex_count ", vertex_count));
    }
  }
  mesh.faces.sizes.assign(message.face_sizes().begin(), message.face_sizes().end());
  mesh.faces.indices.assign(message.face_indices().begin(), message.face_indices().end());
  return mesh;
}

}  // namespace fitbase::proto
