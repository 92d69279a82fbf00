#include "body/target_file.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "core/file_util.h"
#include "core/status_macros.h"
#include "core/text_tokens.h"

namespace fitbase::body {

absl::StatusOr<Target> ParseTarget(absl::string_view text, int64_t vertex_count,
                                   absl::string_view name) {
  std::vector<int32_t> indices;
  std::vector<double> offsets;
  std::vector<bool> seen(static_cast<size_t>(vertex_count), false);
  RETURN_IF_ERROR(core::ForEachDataLine(
      text, absl::StrCat("target ", name), core::CommentStyle::kWholeLine,
      [&](const core::TextLine& line) -> absl::Status {
        const std::vector<absl::string_view>& tokens = *line.tokens;
        if (tokens.size() != 4) return line.Error("expected 'index dx dy dz'");
        int64_t index = 0;
        if (!core::ParseNumber(tokens[0], index)) {
          return line.Error("vertex index is not an integer");
        }
        if (index < 0 || index >= vertex_count) {
          return line.Error(absl::StrCat("vertex index outside [0, ", vertex_count, ")"));
        }
        if (seen[index]) return line.Error("vertex index repeated");
        seen[index] = true;
        indices.push_back(static_cast<int32_t>(index));
        for (int axis = 1; axis <= 3; ++axis) {
          double value = 0.0;
          if (!core::ParseNumber(tokens[axis], value) || !std::isfinite(value)) {
            return line.Error("offset is not a finite number");
          }
          offsets.push_back(value);
        }
        return absl::OkStatus();
      }));
  Target target;
  target.indices = std::move(indices);
  target.offsets = Eigen::Map<const core::Positions>(offsets.data(),
                                               static_cast<Eigen::Index>(offsets.size() / 3), 3)
                       .cast<float>();
  return target;
}

absl::StatusOr<Target> ReadTargetFile(const std::filesystem::path& path, int64_t vertex_count) {
  ASSIGN_OR_RETURN(std::string text, core::ReadFileToString(path));
  return ParseTarget(text, vertex_count, path.string());
}

}  // namespace fitbase::body
