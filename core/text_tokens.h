#ifndef FITBASE_CORE_TEXT_TOKENS_H_
#define FITBASE_CORE_TEXT_TOKENS_H_

#include <charconv>
#include <vector>

#include "absl/strings/string_view.h"

namespace fitbase::core {

// Helpers for the line-oriented text formats fitbase reads (OBJ, .target, .mhclo), whose
// files run to hundreds of thousands of short lines.

// Parses the whole token as a number; false on trailing characters or a range error.
// from_chars rejects a leading '+', which none of these formats writes.
template <typename T>
bool ParseNumber(absl::string_view token, T& value) {
  const char* end = token.data() + token.size();
  auto [ptr, ec] = std::from_chars(token.data(), end, value);
  return ec == std::errc() && ptr == end;
}

// Splits `line` at spaces and tabs into `tokens` (cleared first; its capacity is reused, so a
// caller looping over lines allocates once). By hand, because this Abseil's
// string_view::find_first_of builds a lookup table on every call.
void SplitTokens(absl::string_view line, std::vector<absl::string_view>& tokens);

}  // namespace fitbase::core

#endif  // FITBASE_CORE_TEXT_TOKENS_H_
