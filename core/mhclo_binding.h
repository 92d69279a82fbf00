#ifndef FITBASE_CORE_MHCLO_BINDING_H_
#define FITBASE_CORE_MHCLO_BINDING_H_

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>

#include "Eigen/Core"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "core/mesh.h"

namespace fitbase::core {

// MakeHuman's binding of a garment to the hm08 reference mesh (a `.mhclo` file): every
// garment vertex is a weighted sum of three reference vertices plus an offset scaled by the
// body's size along each axis. It makes a garment grow and shrink with the body, which is the
// `geometric` baseline (no real fit) and how a garment template is placed on the mean avatar.
struct MhcloBinding {
  std::string name;
  std::string obj_file;
  // One row per garment vertex, in the garment OBJ's vertex order.
  Eigen::Matrix<int32_t, Eigen::Dynamic, 3, Eigen::RowMajor> reference_vertices;
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> weights;
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> offsets;  // Data units (dm).
  // x_scale, y_scale, z_scale: the offset along axis a is multiplied by
  // |P[i].a - P[j].a| / reference_distance (reference_distance in data units). The reference
  // distance is that of the body the garment was bound on, where every scale is 1; for the
  // shipped garments that body is never base.obj itself (see body/makehuman_body_test.cc).
  struct AxisScale {
    int32_t i = 0;
    int32_t j = 0;
    double reference_distance = 1.0;
  };
  std::array<AxisScale, 3> scales;

  int64_t vertex_count() const { return reference_vertices.rows(); }
};

// Parses `.mhclo` text; every index must be below `reference_vertex_count`. `name` is used in
// error messages. The vertex block follows `verts 0`, one line per garment vertex,
// `i j k wi wj wk dx dy dz` or a single index `i` (read as `i i i 1 0 0 0 0 0`), and ends at the
// next line that starts with a letter (e.g. `delete_verts`, whose numbers are not vertices) or
// at the end of the text. Lines other than name, obj_file, x/y/z_scale and the vertex block are
// ignored (they do not affect fitting); `#` starts a comment. Errors (INVALID_ARGUMENT, naming
// the line): a missing scale or `verts` line, an empty vertex block, a malformed or non-finite
// number, an index out of range, a reference distance that is not positive. `obj_file` stays
// empty if the file has none.
absl::StatusOr<MhcloBinding> ParseMhclo(absl::string_view text, int64_t reference_vertex_count,
                                        absl::string_view name);

absl::StatusOr<MhcloBinding> ReadMhclo(const std::filesystem::path& path,
                                       int64_t reference_vertex_count);

// Garment positions (N x 3) on a reference mesh with positions `reference` (the full hm08
// mesh, V x 3; every index of `binding` must be below V, as ParseMhclo checks). Output units
// are those of `reference`: offsets are in data units, and the axis scale
// |dP| / reference_distance converts them.
Positions ApplyMhclo(const MhcloBinding& binding, const Positions& reference);

}  // namespace fitbase::core

#endif  // FITBASE_CORE_MHCLO_BINDING_H_
