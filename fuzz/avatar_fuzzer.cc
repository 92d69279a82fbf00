// The common avatar format (`.fba`, ProjectAvatar's request; docs/avatar-format.md), raw or
// Draco: the v1::Avatar message parsed, then proto::AvatarPositions, which validates all of it.
#include <cstdint>

#include "fitbase/v1/avatar.pb.h"
#include "proto/avatar_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fitbase::v1::Avatar avatar;
  if (avatar.ParseFromArray(data, static_cast<int>(size))) {
    (void)fitbase::proto::AvatarPositions(avatar);
  }
  return 0;
}
