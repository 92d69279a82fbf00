#include "core/obj_io.h"

#include <cmath>
#include <sstream>
#include <string>

#include "OpenMesh/Core/IO/MeshIO.hh"
#include "OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "core/file_util.h"
#include "core/garment_obj.h"
#include "core/status_macros.h"

namespace fitbase::core {
namespace {

struct DoubleTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
};
using OpenMeshPolyMesh = OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits>;

struct ElementCounts {
  int64_t vertices = 0;
  int64_t faces = 0;
};

// Counts `v` and `f` lines. OpenMesh skips a vertex line it cannot parse ("nan") and a face it
// cannot add (non-manifold), which would silently shift vertex order or drop topology.
ElementCounts CountObjElements(absl::string_view text) {
  ElementCounts counts;
  for (absl::string_view line : absl::StrSplit(text, '\n')) {
    if (absl::StartsWith(line, "v ") || absl::StartsWith(line, "v\t")) ++counts.vertices;
    if (absl::StartsWith(line, "f ") || absl::StartsWith(line, "f\t")) ++counts.faces;
  }
  return counts;
}

}  // namespace

absl::StatusOr<Mesh> ReadObj(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) {
    return absl::NotFoundError(absl::StrCat("no mesh file ", path.string()));
  }
  ASSIGN_OR_RETURN(std::string text, ReadFileToString(path));
  // Debian's OpenMesh asserts, aborting the process, on some malformed lines (a face line
  // without a vertex index): fitbase's own parser checks every line first and names the bad
  // one. OpenMesh then reads the same bytes, never the file again.
  RETURN_IF_ERROR(ParseGarmentObj(text, path.string()).status());
  OpenMeshPolyMesh om;
  OpenMesh::IO::Options options;
  std::istringstream stream(text);
  if (!OpenMesh::IO::read_mesh(om, stream, "obj", options)) {
    return absl::InvalidArgumentError(absl::StrCat("OpenMesh cannot read ", path.string()));
  }
  if (om.n_vertices() == 0) {
    return absl::InvalidArgumentError(absl::StrCat(path.string(), " has no vertices"));
  }
  const ElementCounts counts = CountObjElements(text);
  if (counts.vertices != static_cast<int64_t>(om.n_vertices())) {
    return absl::InvalidArgumentError(absl::StrCat(
        path.string(), ": ", counts.vertices - static_cast<int64_t>(om.n_vertices()), " of ",
        counts.vertices, " vertex lines are not three finite numbers"));
  }
  if (counts.faces != static_cast<int64_t>(om.n_faces())) {
    return absl::InvalidArgumentError(absl::StrCat(
        path.string(), ": ", counts.faces - static_cast<int64_t>(om.n_faces()), " of ",
        counts.faces, " faces are invalid (bad vertex index or non-manifold)"));
  }
  Mesh mesh;
  mesh.positions.resize(static_cast<Eigen::Index>(om.n_vertices()), 3);
  for (const auto vh : om.vertices()) {
    const OpenMesh::Vec3d& p = om.point(vh);
    for (int axis = 0; axis < 3; ++axis) {
      if (!std::isfinite(p[axis])) {
        return absl::InvalidArgumentError(absl::StrCat(
            path.string(), ": vertex ", vh.idx(), " has a non-finite coordinate"));
      }
      mesh.positions(vh.idx(), axis) = p[axis];
    }
  }
  mesh.faces.sizes.reserve(om.n_faces());
  for (const auto fh : om.faces()) {
    int size = 0;
    for (const auto vh : om.fv_range(fh)) {
      mesh.faces.indices.push_back(vh.idx());
      ++size;
    }
    mesh.faces.sizes.push_back(size);
  }
  return mesh;
}

absl::Status WriteObj(const std::filesystem::path& path, const Mesh& mesh) {
  // No texture coordinates: a body or a fitted garment carries none.
  return WriteGarmentObj(path,
                         GarmentMesh{.mesh = mesh, .texcoords = {}, .face_texcoord_indices = {}});
}

}  // namespace fitbase::core
