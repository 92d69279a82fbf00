#include "core/target_file.h"

#include <cmath>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "core/file_util.h"
#include "core/status_macros.h"
#include "core/text_tokens.h"

namespace fitbase::core {

absl::StatusOr<Target> ParseTarget(absl::string_view text, int64_t vertex_count,
                                   absl::string_view name) {
  std::vector<int32_t> indices;
  std::vector<double> offsets;
  std::vector<bool> seen(static_cast<size_t>(vertex_count), false);
  std::vector<absl::string_view> tokens;
  int line_number = 0;
  for (absl::string_view line : absl::StrSplit(text, '\n')) {
    ++line_number;
    line = absl::StripAsciiWhitespace(line);
    if (line.empty() || line.front() == '#') continue;
    auto error = [&](absl::string_view what) {
      return absl::InvalidArgumentError(
          absl::StrCat("target ", name, " line ", line_number, ": ", what, ": '", line, "'"));
    };
    SplitTokens(line, tokens);
    if (tokens.size() != 4) return error("expected 'index dx dy dz'");
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
