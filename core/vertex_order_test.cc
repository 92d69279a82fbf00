#include "core/vertex_order.h"

#include <algorithm>

#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

TEST(SpatialOrderTest, IsAPermutationThatKeepsNeighboursTogether) {
  // A 20 x 20 grid listed column-major with every other column reversed far away in the
  // list: Z-order must bring each point's grid neighbours near it.
  Positions grid(400, 3);
  for (int i = 0; i < 400; ++i) grid.row(i) << (i * 7 % 20) * 0.01, (i * 7 / 20 % 20) * 0.01, 0;
  const std::vector<uint32_t> order = SpatialOrder(grid);
  std::vector<uint32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (uint32_t i = 0; i < 400; ++i) ASSERT_EQ(sorted[i], i);
  double in_order = 0, as_listed = 0;
  for (int i = 1; i < 400; ++i) {
    in_order += (grid.row(order[i]) - grid.row(order[i - 1])).norm();
    as_listed += (grid.row(i) - grid.row(i - 1)).norm();
  }
  EXPECT_LT(in_order, 0.5 * as_listed);
}

TEST(SpatialOrderTest, DependsOnThePositionsOnly) {
  Positions points(3, 3);
  points << 1, 1, 1, 0, 0, 0, 0.5, 0.5, 0.5;
  EXPECT_EQ(SpatialOrder(points), (std::vector<uint32_t>{1, 2, 0}));
  EXPECT_EQ(SpatialOrder(points), SpatialOrder(points));
  EXPECT_TRUE(SpatialOrder(Positions(0, 3)).empty());
}

}  // namespace
}  // namespace fitbase::core
