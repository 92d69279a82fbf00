#ifndef FITBASE_CLI_API_KEY_SOURCE_H_
#define FITBASE_CLI_API_KEY_SOURCE_H_

#include <filesystem>
#include <string>

#include "absl/status/statusor.h"

namespace fitbase::cli {

// Where command-line clients find their API key. Never a flag: flags show in `ps` and in
// shell history.
inline constexpr char kApiKeyVariable[] = "FITBASE_API_KEY";

// $FITBASE_API_KEY without surrounding whitespace; FAILED_PRECONDITION when it is unset or
// blank, or holds other bytes than printable ASCII (which gRPC metadata cannot carry).
absl::StatusOr<std::string> ApiKeyFromEnvironment();

// The first line of the file at `path` without surrounding whitespace; NOT_FOUND when the file
// cannot be opened, FAILED_PRECONDITION as ApiKeyFromEnvironment.
absl::StatusOr<std::string> ApiKeyFromFile(const std::filesystem::path& path);

}  // namespace fitbase::cli

#endif  // FITBASE_CLI_API_KEY_SOURCE_H_
