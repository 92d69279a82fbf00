#include "proto/json_codec.h"

#include <memory>

#include "absl/strings/str_cat.h"
#include "google/protobuf/descriptor.h"
#include "google/protobuf/util/json_util.h"
#include "google/protobuf/util/type_resolver_util.h"
#include "proto/message_file.h"

namespace fitbase::proto {
namespace {

constexpr absl::string_view kTypeUrlPrefix = "type.googleapis.com";

google::protobuf::util::TypeResolver* GeneratedTypeResolver() {
  static auto* resolver = google::protobuf::util::NewTypeResolverForDescriptorPool(
      std::string(kTypeUrlPrefix), google::protobuf::DescriptorPool::generated_pool());
  return resolver;
}

}  // namespace

absl::Status ParseJson(absl::string_view json, google::protobuf::Message* message) {
  google::protobuf::util::JsonParseOptions options;
  options.ignore_unknown_fields = false;
  const auto status = google::protobuf::util::JsonStringToMessage(
      google::protobuf::StringPiece(json.data(), json.size()), message, options);
  if (!status.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("invalid JSON for ",
                                                   message->GetDescriptor()->full_name(), ": ",
                                                   status.message().as_string()));
  }
  return absl::OkStatus();
}

std::string ToJson(const google::protobuf::Message& message) {
  // The JSON printer follows wire order, and only deterministic serialization sorts maps.
  const std::string binary = SerializeDeterministically(message);
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  options.always_print_primitive_fields = true;
  std::string json;
  // Printing a message we serialized ourselves with the generated pool cannot fail.
  (void)google::protobuf::util::BinaryToJsonString(
      GeneratedTypeResolver(),
      absl::StrCat(kTypeUrlPrefix, "/", message.GetDescriptor()->full_name()), binary, &json,
      options);
  return json;
}

}  // namespace fitbase::proto
