#include "workers/cloth_model.h"

#include <algorithm>

#include "gtest/gtest.h"
#include "workers/test_shapes.h"

namespace fitbase::workers {
namespace {

TEST(ClothModelTest, QuadGridConstraintsAndMasses) {
  // 3 x 3 vertices, 4 quads of 0.1 m: 12 sides + 4 diagonals; 8 interior triangle edges
  // each give one hinge, flat here.
  core::Mesh grid;
  grid.positions.resize(9, 3);
  for (int i = 0; i < 9; ++i) grid.positions.row(i) << 0.1 * (i % 3), 1.0 - 0.1 * (i / 3), 0;
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < 2; ++c) {
      const int a = 3 * r + c;
      grid.faces.sizes.push_back(4);
      grid.faces.indices.insert(grid.faces.indices.end(), {a, a + 3, a + 4, a + 1});
    }
  }
  auto model = BuildClothModel(grid.positions, grid.faces, 0.2);
  ASSERT_TRUE(model.ok()) << model.status();
  EXPECT_EQ(model->triangles.rows(), 8);
  EXPECT_EQ(model->edges.size(), 16u);
  ASSERT_EQ(model->hinges.size(), 8u);
  EXPECT_TRUE((HingeAngles(grid.positions, model->hinges).array().abs() < 1e-12).all());
  // Total mass = area x density = 0.04 m^2 x 0.2 kg/m^2.
  EXPECT_NEAR(model->inverse_masses.cwiseInverse().sum(), 0.008, 1e-12);
  // One piece, one boundary loop: every boundary vertex (all but the centre) on it.
  ASSERT_EQ(model->openings.size(), 1u);
  EXPECT_EQ(model->openings[0].vertices.size(), 8u);
  EXPECT_EQ(model->openings[0].edges.size(), 8u);
  EXPECT_TRUE(model->openings[0].highest_of_piece);
  EXPECT_TRUE(std::is_sorted(model->edges.begin(), model->edges.end()));
  // Each triangle is half a quad at rest; a garment graded 10% larger has 21% more area.
  const Eigen::VectorXd rest = PairLengths(grid.positions, model->edges);
  EXPECT_TRUE(TriangleRestAreas(*model, rest).isConstant(0.005, 1e-9));
  EXPECT_TRUE(TriangleRestAreas(*model, 1.1 * rest).isConstant(0.00605, 1e-9));
  // Rest lengths that cannot close a triangle give no area.
  Eigen::VectorXd broken = rest;
  broken(0) = 1;
  EXPECT_EQ(TriangleRestAreas(*model, broken).minCoeff(), 0);
}

TEST(ClothModelTest, TubeHasTwoOpeningsTheTopOneHighest) {
  const core::Mesh tube = Tube(0.2, 0.0, 0.4, 4, 12);
  auto model = BuildClothModel(tube.positions, tube.faces, 0.2);
  ASSERT_TRUE(model.ok());
  ASSERT_EQ(model->openings.size(), 2u);
  for (const Opening& opening : model->openings) {
    EXPECT_EQ(opening.piece, 0);
    ASSERT_EQ(opening.vertices.size(), 12u);
    ASSERT_EQ(opening.edges.size(), 12u);
    const double height = opening.highest_of_piece ? 0.4 : 0.0;
    EXPECT_DOUBLE_EQ(opening.mean_height, height);
    for (int32_t v : opening.vertices) EXPECT_DOUBLE_EQ(tube.positions(v, 1), height);
    for (int32_t e : opening.edges) {
      for (int32_t v : model->edges[e]) EXPECT_DOUBLE_EQ(tube.positions(v, 1), height);
    }
  }
  EXPECT_NE(model->openings[0].highest_of_piece, model->openings[1].highest_of_piece);
  // Quads are planar and the tube straight, so only the hinges between neighbouring columns
  // fold, by the 12-gon's exterior angle.
  const Eigen::VectorXd angles = HingeAngles(tube.positions, model->hinges);
  EXPECT_NEAR(angles.cwiseAbs().maxCoeff(), 2 * 3.14159265358979323846 / 12, 1e-9);
}

TEST(ClothModelTest, RejectsBadFaces) {
  const core::Mesh tube = Tube(0.2, 0.0, 0.4, 2, 6);
  core::PolygonFaces bad = tube.faces;
  bad.indices[3] = 1000;
  EXPECT_EQ(BuildClothModel(tube.positions, bad, 0.2).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_FALSE(BuildClothModel(tube.positions, core::PolygonFaces{}, 0.2).ok());
}

}  // namespace
}  // namespace fitbase::workers
