#include "core/text_tokens.h"

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

}  // namespace fitbase::core
