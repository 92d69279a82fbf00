// AvatarParams JSON as `fitbase avatar --params` and a population's params.jsonl take it:
// proto::ParseJson, proto::BodyParamsFromProto (the validation), then the MakeHuman target
// weights a body is built from, which assume valid parameters.
#include <cstdint>

#include "absl/strings/string_view.h"
#include "body/macro_weights.h"
#include "fitbase/v1/avatar.pb.h"
#include "proto/avatar_params_codec.h"
#include "proto/json_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fitbase::v1::AvatarParams message;
  if (!fitbase::proto::ParseJson(absl::string_view(reinterpret_cast<const char*>(data), size),
                                 &message)
           .ok()) {
    return 0;
  }
  auto params = fitbase::proto::BodyParamsFromProto(message);
  if (params.ok()) (void)fitbase::body::ComputeTargetWeights(*params);
  return 0;
}
