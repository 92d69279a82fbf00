#include "cli/api_key_source.h"

#include <cstdlib>

#include "absl/status/status.h"
#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "core/file_util.h"
#include "core/status_macros.h"

namespace fitbase::cli {
namespace {

// `source` names where the key came from; errors show a bad byte in hex, never the key.
absl::StatusOr<std::string> CheckedKey(absl::string_view key, absl::string_view source) {
  key = absl::StripAsciiWhitespace(key);
  if (key.empty()) return absl::FailedPreconditionError(absl::StrCat(source, " holds no API key"));
  for (size_t i = 0; i < key.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(key[i]);
    if (c < 0x21 || c > 0x7E) {
      return absl::FailedPreconditionError(absl::StrFormat(
          "the API key in %s has byte 0x%02X at offset %d; keys are printable ASCII", source, c,
          i));
    }
  }
  return std::string(key);
}

}  // namespace

absl::StatusOr<std::string> ApiKeyFromEnvironment() {
  const char* value = std::getenv(kApiKeyVariable);
  if (value == nullptr) {
    return absl::FailedPreconditionError(
        absl::StrCat(kApiKeyVariable, " is not set; it holds the API key for the servers"));
  }
  return CheckedKey(value, kApiKeyVariable);
}

absl::StatusOr<std::string> ApiKeyFromFile(const std::filesystem::path& path) {
  ASSIGN_OR_RETURN(const std::string text, core::ReadFileToString(path));
  const absl::string_view view = text;
  return CheckedKey(view.substr(0, view.find('\n')), path.string());
}

}  // namespace fitbase::cli
