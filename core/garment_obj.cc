#include "core/garment_obj.h"

#include <charconv>
#include <cmath>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "core/file_util.h"
#include "core/status_macros.h"
#include "core/text_tokens.h"

namespace fitbase::core {
namespace {

// Resolves a 1-based (or negative, relative to the `count` elements defined so far) OBJ index
// to a 0-based one; false if it is 0, not an integer, or refers to an element not yet defined.
bool ResolveIndex(absl::string_view token, int64_t count, int32_t& index) {
  int64_t value = 0;
  if (!ParseNumber(token, value)) return false;
  if (value < 0) value += count + 1;
  if (value < 1 || value > count) return false;
  index = static_cast<int32_t>(value - 1);
  return true;
}

}  // namespace

absl::StatusOr<GarmentMesh> ParseGarmentObj(absl::string_view text, absl::string_view name) {
  std::vector<double> positions;
  std::vector<double> texcoords;
  int64_t normal_count = 0;
  GarmentMesh garment;
  PolygonFaces& faces = garment.mesh.faces;
  RETURN_IF_ERROR(ForEachDataLine(
      text, name, CommentStyle::kWholeLine, [&](const TextLine& line) -> absl::Status {
        const std::vector<absl::string_view>& tokens = *line.tokens;
        const absl::string_view keyword = tokens[0];
        const size_t argument_count = tokens.size() - 1;
        if (keyword == "v") {
          // A fourth number is a homogeneous w, three more are a vertex colour (MeshLab, ZBrush);
          // neither matters to a garment's shape.
          if (argument_count != 3 && argument_count != 4 && argument_count != 6) {
            return line.Error("expected 'v x y z' (optionally with w or r g b)");
          }
          for (size_t k = 1; k <= 3; ++k) {
            double value = 0.0;
            if (!ParseNumber(tokens[k], value) || !std::isfinite(value)) {
              return line.Error("coordinate is not a finite number");
            }
            positions.push_back(value);
          }
        } else if (keyword == "vt") {
          if (argument_count != 2 && argument_count != 3) return line.Error("expected 'vt u v'");
          for (size_t k = 1; k <= 2; ++k) {
            double value = 0.0;
            if (!ParseNumber(tokens[k], value) || !std::isfinite(value)) {
              return line.Error("texture coordinate is not a finite number");
            }
            texcoords.push_back(value);
          }
        } else if (keyword == "vn") {
          ++normal_count;
        } else if (keyword == "f") {
          if (argument_count < 3) return line.Error("a face needs at least 3 corners");
          const int64_t vertex_count = static_cast<int64_t>(positions.size() / 3);
          const int64_t texcoord_count = static_cast<int64_t>(texcoords.size() / 2);
          for (size_t k = 1; k <= argument_count; ++k) {
            // v, v/vt, v//vn or v/vt/vn.
            const absl::string_view corner = tokens[k];
            const size_t first_slash = corner.find('/');
            int32_t vertex = 0;
            if (!ResolveIndex(corner.substr(0, first_slash), vertex_count, vertex)) {
              return line.Error(absl::StrCat("corner '", corner, "' does not name one of the ",
                                             vertex_count, " vertices defined so far"));
            }
            int32_t texcoord = -1;
            if (first_slash != absl::string_view::npos) {
              const absl::string_view rest = corner.substr(first_slash + 1);
              const size_t second_slash = rest.find('/');
              const absl::string_view texcoord_token = rest.substr(0, second_slash);
              if (!texcoord_token.empty() &&
                  !ResolveIndex(texcoord_token, texcoord_count, texcoord)) {
                return line.Error(absl::StrCat("corner '", corner, "' does not name one of the ",
                                               texcoord_count,
                                               " texture coordinates defined so far"));
              }
              int32_t normal = 0;
              if (second_slash != absl::string_view::npos &&
                  !ResolveIndex(rest.substr(second_slash + 1), normal_count, normal)) {
                return line.Error(absl::StrCat("corner '", corner, "' does not name one of the ",
                                               normal_count, " normals defined so far"));
              }
              if (second_slash == absl::string_view::npos && texcoord_token.empty()) {
                return line.Error(absl::StrCat("corner '", corner, "' is malformed"));
              }
            }
            faces.indices.push_back(vertex);
            garment.face_texcoord_indices.push_back(texcoord);
          }
          faces.sizes.push_back(static_cast<int32_t>(argument_count));
        }
        return absl::OkStatus();
      }));
  if (positions.empty()) return absl::InvalidArgumentError(absl::StrCat(name, " has no vertices"));
  garment.mesh.positions = Eigen::Map<const Positions>(
      positions.data(), static_cast<Eigen::Index>(positions.size() / 3), 3);
  garment.texcoords = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>(
      texcoords.data(), static_cast<Eigen::Index>(texcoords.size() / 2), 2);
  return garment;
}

absl::StatusOr<GarmentMesh> ReadGarmentObj(const std::filesystem::path& path) {
  ASSIGN_OR_RETURN(std::string text, ReadFileToString(path));
  return ParseGarmentObj(text, path.string());
}

absl::Status WriteGarmentObj(const std::filesystem::path& path, const GarmentMesh& garment) {
  const Mesh& mesh = garment.mesh;
  const PolygonFaces& faces = mesh.faces;
  const std::vector<int32_t>& corner_texcoords = garment.face_texcoord_indices;
  auto invalid = [&](absl::string_view what) {
    return absl::InvalidArgumentError(absl::StrCat("cannot write ", path.string(), ": ", what));
  };
  // Checked before writing: a file that ReadGarmentObj rejects must never replace a good one.
  if (!mesh.positions.allFinite() || !garment.texcoords.allFinite()) {
    return invalid("non-finite coordinates");
  }
  size_t corner_count = 0;
  for (int32_t size : faces.sizes) {
    if (size < 3) return invalid("a face with fewer than 3 corners");
    corner_count += static_cast<size_t>(size);
  }
  if (corner_count != faces.indices.size()) return invalid("face sizes do not match the indices");
  for (int32_t index : faces.indices) {
    if (index < 0 || index >= mesh.vertex_count()) return invalid("a face index out of range");
  }
  if (!corner_texcoords.empty()) {
    if (corner_texcoords.size() != corner_count) {
      return invalid("texture indices are neither one per corner nor none");
    }
    for (int32_t index : corner_texcoords) {
      if (index < -1 || index >= garment.texcoords.rows()) {
        return invalid("a texture index out of range");
      }
    }
  }

  std::string text;
  text.reserve(static_cast<size_t>(mesh.vertex_count()) * 40 +
               static_cast<size_t>(garment.texcoords.rows()) * 28 + corner_count * 12);
  absl::StrAppend(&text, "# fitbase mesh, topology ",
                  mesh.topology_id.empty() ? "unnamed" : mesh.topology_id, ", meters\n");
  for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
    absl::StrAppendFormat(&text, "v %.9g %.9g %.9g\n", mesh.positions(v, 0), mesh.positions(v, 1),
                          mesh.positions(v, 2));
  }
  for (Eigen::Index t = 0; t < garment.texcoords.rows(); ++t) {
    absl::StrAppendFormat(&text, "vt %.9g %.9g\n", garment.texcoords(t, 0),
                          garment.texcoords(t, 1));
  }
  size_t corner = 0;
  for (int32_t size : faces.sizes) {
    text += 'f';
    for (int32_t k = 0; k < size; ++k, ++corner) {
      absl::StrAppend(&text, " ", faces.indices[corner] + 1);
      if (!corner_texcoords.empty() && corner_texcoords[corner] >= 0) {
        absl::StrAppend(&text, "/", corner_texcoords[corner] + 1);
      }
    }
    text += '\n';
  }
  return WriteFileAtomically(path, text);
}

}  // namespace fitbase::core
