#ifndef FITBASE_CORE_FILE_UTIL_H_
#define FITBASE_CORE_FILE_UTIL_H_

#include <filesystem>
#include <string>
#include "absl/strings/string_view.h"

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace fitbase::core {

// Writes `bytes` through a temporary file renamed into place, so a reader or a crash never
// sees half a file.
absl::Status WriteFileAtomically(const std::filesystem::path& path, absl::string_view bytes);

// The whole file; a missing file is NOT_FOUND.
absl::StatusOr<std::string> ReadFileToString(const std::filesystem::path& path);

}  // namespace fitbase::core

#endif  // FITBASE_CORE_FILE_UTIL_H_
