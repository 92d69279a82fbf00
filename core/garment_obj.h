#ifndef FITBASE_CORE_GARMENT_OBJ_H_
#define FITBASE_CORE_GARMENT_OBJ_H_

#include <filesystem>

#include "Eigen/Core"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "core/mesh.h"

namespace fitbase::core {

// A garment mesh exactly as its OBJ file gives it: vertices in file order, every face with its
// corners in file order, and texture coordinates per corner.
struct GarmentMesh {
  Mesh mesh;  // positions in the file's units; faces as given.
  Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> texcoords;  // T x 2 (vt lines).
  // One per entry of mesh.faces.indices: the vt index of that corner, or -1 if none.
  std::vector<int32_t> face_texcoord_indices;
};

// Parses OBJ text with its own parser, not OpenMesh: garments are often non-manifold (a seam
// where three panels meet), and OpenMesh's halfedge importer then duplicates vertices, which
// would break the vertex order every linear garment model depends on. Handles `v` (a trailing
// w or r g b is ignored), `vt`, `f` with v, v/vt, v//vn and v/vt/vn corners, negative
// (relative) indices, comments and other lines (ignored). As in the OBJ format, an index
// refers to an element defined above its face. Errors (INVALID_ARGUMENT) name `name` (a path
// or an upload's name) and the line: non-finite or malformed numbers, an index out of range, a
// face with fewer than 3 corners, text with no vertices.
absl::StatusOr<GarmentMesh> ParseGarmentObj(absl::string_view text, absl::string_view name);

// ParseGarmentObj of the file's contents, named by its path; a missing file is NOT_FOUND.
absl::StatusOr<GarmentMesh> ReadGarmentObj(const std::filesystem::path& path);

// Writes positions and texture coordinates (9 significant digits, so what ReadGarmentObj read
// from a file of at most 9 digits reads back identical) and faces (v/vt corners where a
// texture index exists), through a temporary file renamed into place. An inconsistent garment
// (non-finite values, an index out of range, face sizes not matching the indices, texture
// indices neither one per corner nor none) is INVALID_ARGUMENT and leaves `path` untouched.
absl::Status WriteGarmentObj(const std::filesystem::path& path, const GarmentMesh& garment);

}  // namespace fitbase::core

#endif  // FITBASE_CORE_GARMENT_OBJ_H_
