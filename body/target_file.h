#ifndef FITBASE_BODY_TARGET_FILE_H_
#define FITBASE_BODY_TARGET_FILE_H_

#include <cstdint>
#include <filesystem>
#include "absl/strings/string_view.h"
#include <vector>

#include "absl/status/statusor.h"
#include "core/mesh.h"

namespace fitbase::body {

// A MakeHuman morph target: sparse offsets of some vertices of the reference mesh, in the
// file's units (decimeters). Sparse because most targets move a few thousand of 19,158 vertices.
struct Target {
  std::vector<int32_t> indices;  // Distinct, each in [0, vertex_count).
  // indices.size() x 3. float32: the files hold 3 to 4 decimals, and building a body streams
  // tens of MB of offsets, so half the bytes is nearly half the time.
  Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor> offsets;
};

// Parses the text of a `.target` file: lines `index dx dy dz`, `#` comments, blank lines.
// `name` is used in error messages. Out-of-range or repeated indices, non-finite offsets and
// malformed lines are errors that name the file and line.
absl::StatusOr<Target> ParseTarget(absl::string_view text, int64_t vertex_count,
                                   absl::string_view name);

absl::StatusOr<Target> ReadTargetFile(const std::filesystem::path& path, int64_t vertex_count);

}  // namespace fitbase::body

#endif  // FITBASE_BODY_TARGET_FILE_H_
