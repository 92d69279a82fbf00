#ifndef FITBASE_PROTO_AVATAR_BASIS_CODEC_H_
#define FITBASE_PROTO_AVATAR_BASIS_CODEC_H_

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "core/mesh.h"
#include "core/pca_basis.h"
#include "fitbase/v1/avatar_basis.pb.h"

namespace fitbase::proto {

// The numeric part of an AvatarBasis: mean (a Mesh with `faces`), components (float32,
// component-major), variances, explained variance and training error. The caller sets id,
// selection and provenance.
v1::AvatarBasis AvatarBasisToProto(const core::PcaBasis& basis, absl::string_view topology_id,
                                   const core::PolygonFaces& faces);

// Validates the stored sizes (components = component_count x mean size, one variance and one
// ratio per component) and finiteness before any use.
absl::StatusOr<core::PcaBasis> PcaBasisFromProto(const v1::AvatarBasis& message);

}  // namespace fitbase::proto

#endif  // FITBASE_PROTO_AVATAR_BASIS_CODEC_H_
