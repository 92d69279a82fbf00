#ifndef FITBASE_PROTO_MESSAGE_FILE_H_
#define FITBASE_PROTO_MESSAGE_FILE_H_

#include <filesystem>
#include <string>

#include "absl/status/status.h"
#include "google/protobuf/message.h"

namespace fitbase::proto {

// Binary serialization with map entries sorted, so the same message gives the same bytes.
std::string SerializeDeterministically(const google::protobuf::Message& message);

// Writes SerializeDeterministically(message) atomically.
absl::Status WriteMessageFile(const std::filesystem::path& path,
                              const google::protobuf::Message& message);

// Reads a binary message; a missing file is NOT_FOUND, unparsable bytes INVALID_ARGUMENT.
absl::Status ReadMessageFile(const std::filesystem::path& path, google::protobuf::Message* message);

}  // namespace fitbase::proto

#endif  // FITBASE_PROTO_MESSAGE_FILE_H_
