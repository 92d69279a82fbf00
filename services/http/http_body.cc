#include "services/http/http_body.h"

#include <string>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "google/protobuf/util/json_util.h"
#include "pipeline/avatar_file.h"
#include "proto/avatar_codec.h"

namespace fitbase::http {

absl::Status ParseJsonBody(absl::string_view body, google::protobuf::Message* message) {
  google::protobuf::util::JsonParseOptions options;
  const auto status = google::protobuf::util::JsonStringToMessage(
      google::protobuf::StringPiece(body.data(), body.size()), message, options);
  if (!status.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("the request body is not a valid ",
                                                   message->GetDescriptor()->name(),
                                                   " in JSON: ", status.message().as_string()));
  }
  return absl::OkStatus();
}

absl::StatusOr<v1::Avatar> ParseUploadedAvatar(absl::string_view body,
                                               absl::string_view content_type) {
  if (absl::StartsWith(content_type, "application/octet-stream")) {
    v1::Avatar avatar;
    if (!avatar.ParseFromArray(body.data(), static_cast<int>(body.size()))) {
      return absl::InvalidArgumentError(
          "the upload is not an avatar file (.fba): its bytes do not parse as fitbase.v1.Avatar");
    }
    return avatar;
  }
  absl::StatusOr<core::Mesh> mesh = pipeline::ParseAvatarObj(body, "the uploaded OBJ");
  if (!mesh.ok()) return mesh.status();
  return proto::AvatarFromPositions(mesh->positions, /*draco=*/false);
}

}  // namespace fitbase::http
