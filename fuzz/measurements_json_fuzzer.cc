// A customer's typed measurements as JSON (`fitbase avatar from-measurements --measurements`):
// proto::ParseJson into TypedMeasurements, then pipeline::MeasurementsFromProto, the check the
// fit service's AvatarFromMeasurements runs too.
#include <cstdint>

#include "absl/strings/string_view.h"
#include "fitbase/v1/avatar.pb.h"
#include "pipeline/avatar_from_measurements.h"
#include "proto/json_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fitbase::v1::TypedMeasurements typed;
  if (fitbase::proto::ParseJson(absl::string_view(reinterpret_cast<const char*>(data), size),
                                &typed)
          .ok()) {
    (void)fitbase::pipeline::MeasurementsFromProto(typed);
  }
  return 0;
}
