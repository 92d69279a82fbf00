#include "core/target_file.h"

#include <array>
#include <charconv>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "absl/strings/ascii.h"
#include "core/file_util.h"
#include "core/status_macros.h"

namespace fitbase::core {
namespace {

template <typename T>
bool ParseNumber(absl::string_view token, T& value) {
  // from_chars rejects a leading '+', which no MakeHuman file uses; ".5" needs no special case.
  const char* end = token.data() + token.size();
  auto [ptr, ec] = std::from_chars(token.data(), end, value);
  return ec == std::errc() && ptr == end;
}

}  // namespace

absl::StatusOr<Target> ParseTarget(absl::string_view text, int64_t vertex_count,
                                   absl::string_view name) {
  std::vector<int32_t> indices;
  std::vector<double> offsets;
  std::vector<bool> seen(static_cast<size_t>(vertex_count), false);
  int line_number = 0;
  for (absl::string_view line : absl::StrSplit(text, '\n')) {
    ++line_number;
    line = absl::StripAsciiWhitespace(line);
    if (line.empty() || line.front() == '#') continue;
    auto error = [&](absl::string_view what) {
      return absl::InvalidArgumentError(
          absl::StrCat("target ", name, " line ", line_number, ": ", what, ": '", line, "'"));
    };
    // Split by hand: this loop runs half a million times when a body model loads, and
    // absl::string_view::find_first_of builds a lookup table on every call.
    std::array<absl::string_view, 4> tokens;
    size_t token_count = 0;
    const char* p = line.data();
    const char* const end = p + line.size();
    while (p != end) {
      while (p != end && (*p == ' ' || *p == '\t')) ++p;
      const char* const token_start = p;
      while (p != end && *p != ' ' && *p != '\t') ++p;
      if (p == token_start) break;
      if (token_count < tokens.size()) {
        tokens[token_count] = absl::string_view(token_start, static_cast<size_t>(p - token_start));
      }
      ++token_count;
    }
    if (token_count != tokens.size()) return error("expected 'index dx dy dz'");
    int64_t index = 0;
    if (!ParseNumber(tokens[0], index)) return error("vertex index is not an integer");
    if (index < 0 || index >= vertex_count) {
      return error(absl::StrCat("vertex index outside [0, ", vertex_count, ")"));
    }
    if (seen[index]) return error("vertex index repeated");
    seen[index] = true;
    indices.push_back(static_cast<int32_t>(index));
    for (int axis = 1; axis <= 3; ++axis) {
      double value = 0.0;
      if (!ParseNumber(tokens[axis], value) || !std::isfinite(value)) {
        return error("offset is not a finite number");
      }
      offsets.push_back(value);
    }
  }
  Target target;
  target.indices = std::move(indices);
  target.offsets = Eigen::Map<const Positions>(offsets.data(),
                                               static_cast<Eigen::Index>(offsets.size() / 3), 3)
                       .cast<float>();
  return target;
}

absl::StatusOr<Target> ReadTargetFile(const std::filesystem::path& path, int64_t vertex_count) {
  ASSIGN_OR_RETURN(std::string text, ReadFileToString(path));
  return ParseTarget(text, vertex_count, path.string());
}

}  // namespace fitbase::core
