// The HTTP API's request bodies (docs/http-api.md), as its handlers parse them: the first byte
// picks the endpoint, the rest is the body. JSON bodies go through the protobuf JSON mapping
// and then the validation the fit service applies first (typed measurements); uploads through
// the OBJ or .fba parser and the avatar's own validation.
#include <cstdint>
#include <string>

#include "absl/strings/string_view.h"
#include "fitbase/v1/fit_service.pb.h"
#include "pipeline/avatar_from_measurements.h"
#include "proto/avatar_codec.h"
#include "services/http/http_body.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const absl::string_view body(reinterpret_cast<const char*>(data) + 1, size - 1);
  switch (data[0] % 4) {
    case 0: {
      fitbase::v1::TryOnRequest request;
      (void)fitbase::http::ParseJsonBody(body, &request);
      break;
    }
    case 1: {
      fitbase::v1::AvatarFromMeasurementsRequest request;
      if (fitbase::http::ParseJsonBody(body, &request).ok()) {
        (void)fitbase::pipeline::MeasurementsFromProto(request.measurements());
      }
      break;
    }
    default: {
      const char* type = data[0] % 4 == 2 ? "text/plain" : "application/octet-stream";
      auto avatar = fitbase::http::ParseUploadedAvatar(body, type);
      if (avatar.ok()) (void)fitbase::proto::AvatarPositions(*avatar);
      break;
    }
  }
  return 0;
}
