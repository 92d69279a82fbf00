#include "core/vertex_order.h"

#include <algorithm>
#include <numeric>

namespace fitbase::core {
namespace {

constexpr int kBits = 10;

// The bits of v spread to every third bit position.
uint64_t Spread(uint64_t v) {
  uint64_t x = v & 0x3ff;
  x = (x | (x << 16)) & 0x030000ff;
  x = (x | (x << 8)) & 0x0300f00f;
  x = (x | (x << 4)) & 0x030c30c3;
  x = (x | (x << 2)) & 0x09249249;
  return x;
}

}  // namespace

std::vector<uint32_t> SpatialOrder(const Positions& positions) {
  const Eigen::Index count = positions.rows();
  std::vector<uint32_t> order(static_cast<size_t>(count));
  std::iota(order.begin(), order.end(), 0u);
  if (count == 0) return order;
  const Eigen::RowVector3d low = positions.colwise().minCoeff();
  const double extent = std::max((positions.colwise().maxCoeff() - low).maxCoeff(), 1e-12);
  const double scale = ((1 << kBits) - 1) / extent;
  std::vector<uint64_t> codes(static_cast<size_t>(count));
  for (Eigen::Index v = 0; v < count; ++v) {
    uint64_t code = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const auto cell = static_cast<uint64_t>((positions(v, axis) - low(axis)) * scale + 0.5);
      code |= Spread(cell) << axis;
    }
    codes[static_cast<size_t>(v)] = code;
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return codes[a] < codes[b]; });
  return order;
}

}  // namespace fitbase::core
