#include "core/text_tokens.h"

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"

namespace fitbase::core {

void SplitTokens(absl::string_view line, std::vector<absl::string_view>& tokens) {
  tokens.clear();
  const char* p = line.data();
  const char* const end = p + line.size();
  while (p != end) {
    while (p != end && (*p == ' ' || *p == '\t')) ++p;
    const char* const token_start = p;
    while (p != end && *p != ' ' && *p != '\t') ++p;
    if (p == token_start) break;
    tokens.emplace_back(token_start, static_cast<size_t>(p - token_start));
  }
}

absl::Status TextLine::Error(absl::string_view what) const {
  return absl::InvalidArgumentError(
      absl::StrCat(label, " line ", number, ": ", what, ": '", text, "'"));
}

absl::Status ForEachDataLine(absl::string_view text, absl::string_view label,
                             CommentStyle comments,
                             absl::FunctionRef<absl::Status(const TextLine&)> fn) {
  std::vector<absl::string_view> tokens;
  TextLine line;
  line.tokens = &tokens;
  line.label = label;
  for (absl::string_view raw : absl::StrSplit(text, '\n')) {
    ++line.number;
    if (comments == CommentStyle::kTrailing) raw = raw.substr(0, raw.find('#'));
    line.text = absl::StripAsciiWhitespace(raw);
    if (line.text.empty() || line.text.front() == '#') continue;
    SplitTokens(line.text, tokens);
    if (absl::Status status = fn(line); !status.ok()) return status;
  }
  return absl::OkStatus();
}

}  // namespace fitbase::core
