#ifndef FITBASE_PROTO_JSON_CODEC_H_
#define FITBASE_PROTO_JSON_CODEC_H_

#include <string>
#include "absl/strings/string_view.h"

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "google/protobuf/message.h"

namespace fitbase::proto {

// Parses proto3 JSON into `message`. Unknown field names are errors (a misspelt parameter
// must not silently become a default).
absl::Status ParseJson(absl::string_view json, google::protobuf::Message* message);

// One-line JSON with proto field names, every field printed, map entries sorted by key, so
// the same message always gives the same bytes.
std::string ToJson(const google::protobuf::Message& message);

}  // namespace fitbase::proto

#endif  // FITBASE_PROTO_JSON_CODEC_H_
