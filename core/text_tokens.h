#ifndef FITBASE_CORE_TEXT_TOKENS_H_
#define FITBASE_CORE_TEXT_TOKENS_H_

#include <charconv>
#include <vector>

#include "absl/functional/function_ref.h"
#include "absl/status/status.h"
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

// One data line of a text file, as ForEachDataLine hands it over.
struct TextLine {
  absl::string_view text;                    // Without comment and surrounding whitespace.
  int number = 0;                            // 1-based.
  const std::vector<absl::string_view>* tokens = nullptr;  // SplitTokens(text).
  absl::string_view label;                   // Names the file in errors.
  // INVALID_ARGUMENT "<label> line <number>: <what>: '<text>'".
  absl::Status Error(absl::string_view what) const;
};

// Where a comment may start: only at the start of a line (OBJ, .target), or anywhere, the rest
// of the line being the comment (.mhclo).
enum class CommentStyle { kWholeLine, kTrailing };

// Calls `fn` for every line of `text` that is not blank or a comment, in order, and stops at
// the first error it returns.
absl::Status ForEachDataLine(absl::string_view text, absl::string_view label,
                             CommentStyle comments,
                             absl::FunctionRef<absl::Status(const TextLine&)> fn);

}  // namespace fitbase::core

#endif  // FITBASE_CORE_TEXT_TOKENS_H_
