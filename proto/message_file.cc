#include "proto/message_file.h"

#include "absl/strings/str_cat.h"
#include "core/file_util.h"
#include "core/status_macros.h"
#include "google/protobuf/io/coded_stream.h"
#include "google/protobuf/io/zero_copy_stream_impl_lite.h"

namespace fitbase::proto {

std::string SerializeDeterministically(const google::protobuf::Message& message) {
  std::string bytes;
  google::protobuf::io::StringOutputStream stream(&bytes);
  google::protobuf::io::CodedOutputStream coded(&stream);
  coded.SetSerializationDeterministic(true);
  message.SerializeToCodedStream(&coded);
  coded.Trim();
  return bytes;
}

absl::Status WriteMessageFile(const std::filesystem::path& path,
                              const google::protobuf::Message& message) {
  return core::WriteFileAtomically(path, SerializeDeterministically(message));
}

absl::Status ReadMessageFile(const std::filesystem::path& path,
                             google::protobuf::Message* message) {
  ASSIGN_OR_RETURN(std::string bytes, core::ReadFileToString(path));
  if (!message->ParseFromString(bytes)) {
    return absl::InvalidArgumentError(absl::StrCat(
        path.string(), " is not a ", message->GetDescriptor()->full_name(), " message"));
  }
  return absl::OkStatus();
}

}  // namespace fitbase::proto
