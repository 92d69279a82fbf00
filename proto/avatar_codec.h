#ifndef FITBASE_PROTO_AVATAR_CODEC_H_
#define FITBASE_PROTO_AVATAR_CODEC_H_

#include <cstdint>

#include "absl/status/statusor.h"
#include "core/mesh.h"
#include "fitbase/v1/avatar.pb.h"

namespace fitbase::proto {

// The format_version of the v1::Avatar messages this code reads and writes.
inline constexpr uint32_t kAvatarFormatVersion = 1;

// The body's positions, body::kBodyVertexCount x 3, meters, hm08 vertex order. Validates the
// whole message (docs/avatar-format.md lists the errors), each failure INVALID_ARGUMENT naming
// it: format_version other than kAvatarFormatVersion, topology_id other than
// body::kBodyTopologyId, positions (see DecodePositions) that are not 13,380 finite vertices,
// a body not 0.5 to 2.5 m tall along +y (the unit it seems to be in is named) or whose bounding
// box centre is more than 0.5 m from MakeHuman's origin, measurements out of range for meters,
// params out of range (see BodyParamsFromProto).
absl::StatusOr<core::Positions> AvatarPositions(const v1::Avatar& avatar);

// An avatar message of `positions` (body::kBodyVertexCount x 3, meters, hm08 order), raw
// float32 or, if `draco`, Draco at DracoSettings{} (11 bits: about 0.4 mm). `params`, if not
// null, is stored as given. The positions are validated as AvatarPositions does.
absl::StatusOr<v1::Avatar> AvatarFromPositions(const core::Positions& positions, bool draco,
                                               const v1::AvatarParams* params = nullptr);

}  // namespace fitbase::proto

#endif  // FITBASE_PROTO_AVATAR_CODEC_H_
