#ifndef FITBASE_PROTO_AVATAR_PARAMS_CODEC_H_
#define FITBASE_PROTO_AVATAR_PARAMS_CODEC_H_

#include "absl/status/statusor.h"
#include "body/body_params.h"
#include "fitbase/v1/avatar.pb.h"

namespace fitbase::proto {

// Unset fields take MakeHuman's defaults; the result is validated (ranges, ethnic sum,
// modifier names), so a bad message is an error naming the parameter, never a silent default.
absl::StatusOr<body::BodyParams> BodyParamsFromProto(const v1::AvatarParams& message);

// Every field set, so a stored message says exactly which body it made.
v1::AvatarParams BodyParamsToProto(const body::BodyParams& params);

}  // namespace fitbase::proto

#endif  // FITBASE_PROTO_AVATAR_PARAMS_CODEC_H_
