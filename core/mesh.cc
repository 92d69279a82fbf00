#include "core/mesh.h"

namespace fitbase::core {

std::vector<float> InterleavedFloats(const Positions& positions) {
  // Row-major: the rows' coordinates are already interleaved in memory.
  return std::vector<float>(positions.data(), positions.data() + positions.size());
}

Triangles Triangulate(const PolygonFaces& faces) {
  Eigen::Index count = 0;
  for (int32_t size : faces.sizes) count += size - 2;
  Triangles triangles(count, 3);
  Eigen::Index t = 0;
  size_t corner = 0;
  for (int32_t size : faces.sizes) {
    for (int32_t k = 1; k + 1 < size; ++k) {
      triangles.row(t++) << faces.indices[corner], faces.indices[corner + k],
          faces.indices[corner + k + 1];
    }
    corner += static_cast<size_t>(size);
  }
  return triangles;
}

}  // namespace fitbase::core
