#ifndef FITBASE_CORE_OBJ_IO_H_
#define FITBASE_CORE_OBJ_IO_H_

#include <filesystem>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "core/mesh.h"

namespace fitbase::core {

// Reads a Wavefront OBJ through OpenMesh. Vertex order and the corner order of each face are
// kept as in the file. Positions are returned in the file's units; `topology_id` stays empty.
// Errors: unreadable file, no vertices, non-finite coordinates, a malformed line (as
// ParseGarmentObj names it: a face with fewer than 3 corners or an undefined index, ...).
absl::StatusOr<Mesh> ReadObj(const std::filesystem::path& path);

// Writes positions (9 significant digits, enough to round-trip float32) and faces, in order,
// through WriteGarmentObj (the one OBJ writer): a mesh it would not read back is an error, and
// the file is written to a temporary name and renamed, so readers never see half a mesh.
absl::Status WriteObj(const std::filesystem::path& path, const Mesh& mesh);

}  // namespace fitbase::core

#endif  // FITBASE_CORE_OBJ_IO_H_
