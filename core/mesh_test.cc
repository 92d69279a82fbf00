#include "core/mesh.h"

#include <array>
#include <vector>

#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

using Rows = std::vector<std::array<int32_t, 3>>;

Rows RowsOf(const Triangles& triangles) {
  Rows rows;
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    rows.push_back({triangles(t, 0), triangles(t, 1), triangles(t, 2)});
  }
  return rows;
}

TEST(TriangulateTest, TriangleIsUnchanged) {
  EXPECT_EQ(RowsOf(Triangulate(PolygonFaces{.sizes = {3}, .indices = {4, 9, 2}})),
            (Rows{{4, 9, 2}}));
}

TEST(TriangulateTest, QuadSplitsIntoTwoTrianglesWithItsOrientation) {
  // Both halves must wind like the quad: 7 -> 3 -> 5 -> 1.
  EXPECT_EQ(RowsOf(Triangulate(PolygonFaces{.sizes = {4}, .indices = {7, 3, 5, 1}})),
            (Rows{{7, 3, 5}, {7, 5, 1}}));
}

TEST(TriangulateTest, PentagonBecomesAFanFromItsFirstCorner) {
  EXPECT_EQ(RowsOf(Triangulate(PolygonFaces{.sizes = {5}, .indices = {0, 1, 2, 3, 4}})),
            (Rows{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}}));
}

TEST(TriangulateTest, MixedFacesKeepTheirOrder) {
  const PolygonFaces faces{.sizes = {4, 3, 5}, .indices = {0, 1, 2, 3, 3, 2, 4, 5, 6, 7, 8, 9}};
  EXPECT_EQ(RowsOf(Triangulate(faces)),
            (Rows{{0, 1, 2}, {0, 2, 3}, {3, 2, 4}, {5, 6, 7}, {5, 7, 8}, {5, 8, 9}}));
}

TEST(TriangulateTest, NoFacesGiveNoTriangles) { EXPECT_EQ(Triangulate(PolygonFaces{}).rows(), 0); }

TEST(MeshTest, InterleavedFloatsListsEachVertexsCoordinatesInTurn) {
  Positions positions(2, 3);
  positions << 0.25, 1.5, -2, 3, 4.5, 5;
  EXPECT_EQ(InterleavedFloats(positions), (std::vector<float>{0.25f, 1.5f, -2, 3, 4.5f, 5}));
}

TEST(MeshTest, TriangleCrossPointsOutOfACounterClockwiseTriangleAndIsTwiceItsArea) {
  Positions positions(4, 3);
  positions << 9, 9, 9, 1, 0, 0, 3, 0, 0, 1, 2, 0;
  Triangles triangles(2, 3);
  triangles << 1, 2, 3, 1, 3, 2;
  // Legs 2 and 2 in the z = 0 plane: area 2, seen counter-clockwise from +z.
  EXPECT_EQ(TriangleCross(positions, triangles, 0), Eigen::Vector3d(0, 0, 4));
  EXPECT_EQ(TriangleCross(positions, triangles, 1), Eigen::Vector3d(0, 0, -4));
}

TEST(MeshTest, VertexNormalsWeighTheirTrianglesByAreaAndLeaveUnusedVerticesZero) {
  // Two triangles folded along the x axis: one in the z = 0 plane (area 2, normal +z), one in
  // the y = 0 plane (area 1, normal -y). Vertex 4 is in no triangle.
  Positions positions(5, 3);
  positions << 0, 0, 0, 2, 0, 0, 0, 2, 0, 0, 0, 1, 7, 7, 7;
  Triangles triangles(2, 3);
  triangles << 0, 1, 2, 0, 1, 3;
  const Positions normals = VertexNormals(positions, triangles);
  // On the fold the larger triangle's normal weighs twice the smaller's: (0, -1, 2).
  const Eigen::RowVector3d fold = Eigen::RowVector3d(0, -1, 2).normalized();
  EXPECT_TRUE(normals.row(0).isApprox(fold)) << normals.row(0);
  EXPECT_TRUE(normals.row(1).isApprox(fold)) << normals.row(1);
  EXPECT_EQ(normals.row(2), Eigen::RowVector3d(0, 0, 1));
  EXPECT_EQ(normals.row(3), Eigen::RowVector3d(0, -1, 0));
  EXPECT_EQ(normals.row(4), Eigen::RowVector3d::Zero());
}

}  // namespace
}  // namespace fitbase::core
