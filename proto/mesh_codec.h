#ifndef FITBASE_PROTO_MESH_CODEC_H_
#define FITBASE_PROTO_MESH_CODEC_H_

#include "absl/status/statusor.h"
#include "core/mesh.h"
#include "fitbase/v1/mesh.pb.h"

namespace fitbase::proto {

// Positions are narrowed to float32 meters, the wire and file precision.
v1::Mesh MeshToProto(const core::Mesh& mesh);

// Validates the message: positions count = 3 * vertex_count, finite values, face sizes >= 3
// summing to the number of indices, indices < vertex_count.
absl::StatusOr<core::Mesh> MeshFromProto(const v1::Mesh& message);

}  // namespace fitbase::proto

#endif  // FITBASE_PROTO_MESH_CODEC_H_
