#include "core/mhclo_binding.h"

#include <charconv>
#include <cmath>
#include <vector>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "core/file_util.h"
#include "core/status_macros.h"
#include "core/text_tokens.h"

namespace fitbase::core {
namespace {

constexpr std::array<absl::string_view, 3> kScaleKeywords = {"x_scale", "y_scale", "z_scale"};

}  // namespace

absl::StatusOr<MhcloBinding> ParseMhclo(absl::string_view text, int64_t reference_vertex_count,
                                        absl::string_view name) {
  MhcloBinding binding;
  std::vector<int32_t> references;
  std::vector<double> weights;
  std::vector<double> offsets;
  std::array<bool, 3> has_scale = {false, false, false};
  bool has_verts = false;
  bool in_verts = false;
  RETURN_IF_ERROR(ForEachDataLine(
      text, absl::StrCat("mhclo ", name), CommentStyle::kTrailing,
      [&](const TextLine& line) -> absl::Status {
        const std::vector<absl::string_view>& tokens = *line.tokens;
        auto parse_index = [&](absl::string_view token, int32_t& index) -> absl::Status {
          int64_t value = 0;
          if (!ParseNumber(token, value)) return line.Error("vertex index is not an integer");
          if (value < 0 || value >= reference_vertex_count) {
            return line.Error(
                absl::StrCat("reference vertex index outside [0, ", reference_vertex_count, ")"));
          }
          index = static_cast<int32_t>(value);
          return absl::OkStatus();
        };

        // A keyword ends the vertex block; the lines of numbers after other keywords
        // (delete_verts ranges such as `1355 - 1388`) are not vertices.
        if (absl::ascii_isalpha(static_cast<unsigned char>(line.text.front()))) {
          in_verts = false;
          const absl::string_view keyword = tokens[0];
          const absl::string_view argument =
              absl::StripLeadingAsciiWhitespace(line.text.substr(keyword.size()));
          if (keyword == "name") {
            binding.name = std::string(argument);
          } else if (keyword == "obj_file") {
            binding.obj_file = std::string(argument);
          } else if (keyword == "verts") {
            // MakeHuman ignores the argument (always `verts 0`).
            if (has_verts) return line.Error("a second 'verts' block");
            has_verts = true;
            in_verts = true;
          } else {
            for (int axis = 0; axis < 3; ++axis) {
              if (keyword != kScaleKeywords[axis]) continue;
              if (has_scale[axis]) return line.Error(absl::StrCat("repeated ", keyword));
              if (tokens.size() != 4) {
                return line.Error(
                    absl::StrCat("expected '", keyword, " i j reference_distance'"));
              }
              MhcloBinding::AxisScale& scale = binding.scales[axis];
              RETURN_IF_ERROR(parse_index(tokens[1], scale.i));
              RETURN_IF_ERROR(parse_index(tokens[2], scale.j));
              if (!ParseNumber(tokens[3], scale.reference_distance) ||
                  !std::isfinite(scale.reference_distance) || scale.reference_distance <= 0.0) {
                return line.Error("reference distance is not a positive finite number");
              }
              has_scale[axis] = true;
            }
          }
          return absl::OkStatus();
        }
        if (!in_verts) return absl::OkStatus();

        std::array<int32_t, 3> vertex_references{};
        std::array<double, 6> values = {1.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        if (tokens.size() == 1) {
          RETURN_IF_ERROR(parse_index(tokens[0], vertex_references[0]));
          // The unused references repeat the bound vertex so every index stays valid.
          vertex_references[1] = vertex_references[2] = vertex_references[0];
        } else if (tokens.size() == 9) {
          for (int k = 0; k < 3; ++k) {
            RETURN_IF_ERROR(parse_index(tokens[k], vertex_references[k]));
          }
          for (int k = 0; k < 6; ++k) {
            if (!ParseNumber(tokens[3 + k], values[k]) || !std::isfinite(values[k])) {
              return line.Error(k < 3 ? "weight is not a finite number"
                                      : "offset is not a finite number");
            }
          }
        } else {
          return line.Error("expected 'i j k wi wj wk dx dy dz' or a single index 'i'");
        }
        references.insert(references.end(), vertex_references.begin(), vertex_references.end());
        weights.insert(weights.end(), values.begin(), values.begin() + 3);
        offsets.insert(offsets.end(), values.begin() + 3, values.end());
        return absl::OkStatus();
      }));

  for (int axis = 0; axis < 3; ++axis) {
    if (!has_scale[axis]) {
      return absl::InvalidArgumentError(
          absl::StrCat("mhclo ", name, ": no ", kScaleKeywords[axis], " line"));
    }
  }
  if (!has_verts) {
    return absl::InvalidArgumentError(absl::StrCat("mhclo ", name, ": no 'verts' line"));
  }
  if (references.empty()) {
    return absl::InvalidArgumentError(
        absl::StrCat("mhclo ", name, ": no vertex lines after 'verts'"));
  }
  const Eigen::Index count = static_cast<Eigen::Index>(references.size() / 3);
  binding.reference_vertices =
      Eigen::Map<const Eigen::Matrix<int32_t, Eigen::Dynamic, 3, Eigen::RowMajor>>(
          references.data(), count, 3);
  binding.weights = Eigen::Map<const Positions>(weights.data(), count, 3);
  binding.offsets = Eigen::Map<const Positions>(offsets.data(), count, 3);
  return binding;
}

absl::StatusOr<MhcloBinding> ReadMhclo(const std::filesystem::path& path,
                                       int64_t reference_vertex_count) {
  ASSIGN_OR_RETURN(std::string text, ReadFileToString(path));
  return ParseMhclo(text, reference_vertex_count, path.string());
}

Positions ApplyMhclo(const MhcloBinding& binding, const Positions& reference) {
  Eigen::Array<double, 1, 3> scale;
  for (int axis = 0; axis < 3; ++axis) {
    const MhcloBinding::AxisScale& s = binding.scales[axis];
    scale(axis) = std::abs(reference(s.i, axis) - reference(s.j, axis)) / s.reference_distance;
  }
  const auto& r = binding.reference_vertices;
  const auto& w = binding.weights;
  return (reference(r.col(0), Eigen::all).array().colwise() * w.col(0).array() +
          reference(r.col(1), Eigen::all).array().colwise() * w.col(1).array() +
          reference(r.col(2), Eigen::all).array().colwise() * w.col(2).array() +
          binding.offsets.array().rowwise() * scale)
      .matrix();
}

}  // namespace fitbase::core
