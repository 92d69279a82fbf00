#ifndef FITBASE_PROTO_GARMENT_CODEC_H_
#define FITBASE_PROTO_GARMENT_CODEC_H_

#include <vector>

#include "absl/status/statusor.h"
#include "body/body_skeleton.h"
#include "core/garment_obj.h"
#include "core/mhclo_binding.h"
#include "fitbase/v1/garment.pb.h"

namespace fitbase::proto {

v1::MhcloBinding MhcloBindingToProto(const core::MhcloBinding& binding);
// Validates counts (3 per vertex, 3 scales) against `vertex_count` garment vertices, and every
// reference index against `reference_vertex_count` (the hm08 mesh's).
absl::StatusOr<core::MhcloBinding> MhcloBindingFromProto(const v1::MhcloBinding& message,
                                                         int64_t vertex_count,
                                                         int64_t reference_vertex_count);

// A garment mesh from the parts Garment and ClothingBasis store: the mesh, 2 texture
// coordinates per vt, one vt index per face corner (or none), validated.
absl::StatusOr<core::GarmentMesh> GarmentMeshFromProto(
    const v1::Mesh& mesh, const google::protobuf::RepeatedField<float>& texcoords,
    const google::protobuf::RepeatedField<int32_t>& face_texcoord_indices);

// The template mesh with its texture coordinates, validated.
absl::StatusOr<core::GarmentMesh> GarmentTemplateFromProto(const v1::Garment& garment);

// Per-vertex length axes (V x 3) and regions, validated against the template's vertex count.
absl::StatusOr<core::Positions> LengthAxesFromProto(const v1::Garment& garment);
absl::StatusOr<std::vector<body::BodyRegion>> RegionsFromProto(const v1::Garment& garment);

}  // namespace fitbase::proto

#endif  // FITBASE_PROTO_GARMENT_CODEC_H_
