#ifndef FITBASE_SERVICES_HTTP_HTTP_BODY_H_
#define FITBASE_SERVICES_HTTP_HTTP_BODY_H_

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "fitbase/v1/avatar.pb.h"
#include "google/protobuf/message.h"

namespace fitbase::http {

// The bytes of an HTTP request, as the API's handlers read them: the only parsers of outside
// bytes in this room, kept apart from the server so that a fuzzer reaches them
// (fuzz/http_body_fuzzer.cc).

// A JSON body into `message` (the protobuf JSON mapping, unknown fields refused).
// INVALID_ARGUMENT naming the message and the parser's complaint.
absl::Status ParseJsonBody(absl::string_view body, google::protobuf::Message* message);

// An uploaded body: an Avatar message (`.fba`) when `content_type` is
// application/octet-stream, else an OBJ's text, checked as an hm08 avatar in meters.
// INVALID_ARGUMENT naming the problem.
absl::StatusOr<v1::Avatar> ParseUploadedAvatar(absl::string_view body,
                                               absl::string_view content_type);

}  // namespace fitbase::http

#endif  // FITBASE_SERVICES_HTTP_HTTP_BODY_H_
