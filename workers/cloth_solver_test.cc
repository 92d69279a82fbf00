#include "workers/cloth_solver.h"

#include "gtest/gtest.h"
#include "workers/test_shapes.h"

namespace fitbase::workers {
namespace {

constexpr double kRadius = 0.1;

// Two spheres side by side along x, `gap` apart (negative: overlapping), as one triangle soup:
// the two sides of a crease, like thighs.
core::TriangleBvh TwoSpheres(double gap) {
  const core::Mesh a = UvSphere(kRadius, 64, 96, Eigen::RowVector3d(-kRadius - gap / 2, 0, 0));
  const core::Mesh b = UvSphere(kRadius, 64, 96, Eigen::RowVector3d(kRadius + gap / 2, 0, 0));
  core::Positions positions(a.positions.rows() + b.positions.rows(), 3);
  positions << a.positions, b.positions;
  const core::Triangles ta = core::Triangulate(a.faces);
  core::Triangles triangles(2 * ta.rows(), 3);
  triangles << ta, (ta.array() + static_cast<int32_t>(a.positions.rows())).matrix();
  return *core::TriangleBvh::Build(positions, triangles);
}

// The cloth model of a garment that is one triangle, its three positions' only face.
ClothModel OneTriangleModel(const core::Positions& garment) {
  core::PolygonFaces faces;
  faces.sizes = {3};
  faces.indices = {0, 1, 2};
  return *BuildClothModel(garment, faces, 0.15);
}

// Pushes a small triangle's first corner, at `inside`, out of `body`; returns its signed
// distance afterwards, m.
double PushedDistance(const core::TriangleBvh& body, const Eigen::RowVector3d& inside) {
  core::Positions garment(3, 3);
  garment << inside, inside + Eigen::RowVector3d(0, 0.01, 0.05),
      inside + Eigen::RowVector3d(0, -0.01, 0.05);
  const ClothModel model = OneTriangleModel(garment);
  ClothSolver solver(model, garment, PairLengths(garment, model.edges),
                     HingeAngles(garment, model.hinges), {}, body, ClothSettings{});
  solver.ResolveCollisions(body, 0.05, 0.001);
  return body.Closest(solver.positions().row(0).transpose(), 0.05).signed_distance;
}

TEST(ClothSolverTest, PushOutFitsBetweenTheSidesOfANarrowCrease) {
  const core::TriangleBvh body = TwoSpheres(0.001);
  const Eigen::RowVector3d inside(-0.0012, 0, 0.01);
  const core::SurfacePoint hit = body.Closest(inside.transpose(), 0.05);
  ASSERT_LT(hit.signed_distance, 0);
  // The point at the full offset over the near side is inside the far one.
  ASSERT_LT(body.Closest(hit.point + ClothSettings{}.collision_offset * hit.normal, 0.05)
                .signed_distance,
            0);
  EXPECT_GT(PushedDistance(body, inside), 0);
}

TEST(ClothSolverTest, PushOutLeavesACreaseWhoseSidesTouchAlongIt) {
  const core::TriangleBvh body = TwoSpheres(-0.0005);
  const Eigen::RowVector3d inside(-0.0014, 0, 0.007);
  const core::SurfacePoint hit = body.Closest(inside.transpose(), 0.05);
  ASSERT_LT(hit.signed_distance, 0);
  for (double lift = ClothSettings{}.collision_offset; lift > 1e-4; lift /= 2) {
    ASSERT_LT(body.Closest(hit.point + lift * hit.normal, 0.05).signed_distance, 0) << lift;
  }
  EXPECT_GT(PushedDistance(body, inside), 0);
}

// Two boxes facing each other across x = 0, `gap` apart, each 10 mm deep and 15 mm square.
core::TriangleBvh TwoFacingBoxes(double gap) {
  constexpr double kDepth = 0.01, kHalfSide = 0.0075;
  const int32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                               {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  core::Positions positions(16, 3);
  core::Triangles triangles(24, 3);
  for (int box = 0; box < 2; ++box) {
    const double x0 = box == 0 ? -gap / 2 - kDepth : gap / 2;
    for (int c = 0; c < 8; ++c) {
      positions.row(8 * box + c) << x0 + ((c & 4) ? kDepth : 0), (c & 2) ? kHalfSide : -kHalfSide,
          (c & 1) ? kHalfSide : -kHalfSide;
    }
    for (int q = 0; q < 6; ++q) {
      const int32_t o = 8 * box;
      triangles.row(12 * box + 2 * q) << o + quads[q][0], o + quads[q][2], o + quads[q][1];
      triangles.row(12 * box + 2 * q + 1) << o + quads[q][0], o + quads[q][3], o + quads[q][2];
    }
  }
  return *core::TriangleBvh::Build(positions, triangles);
}

TEST(ClothSolverTest, PushOutLeavesACreaseTooNarrowToFitInWhoseSidesFaceSquarely) {
  // As under a heavy man's arm: the sides 0.05 mm apart, narrower than the least lift, and
  // facing each other squarely, so that no way leads out along the crease.
  const core::TriangleBvh body = TwoFacingBoxes(0.00005);
  const Eigen::RowVector3d inside(-0.000125, 0.001, 0.002);
  const core::SurfacePoint hit = body.Closest(inside.transpose(), 0.05);
  ASSERT_LT(hit.signed_distance, 0);
  const double offset = ClothSettings{}.collision_offset;
  for (double lift = offset; lift > 1e-4; lift /= 2) {
    ASSERT_LT(body.Closest(hit.point + lift * hit.normal, 0.05).signed_distance, 0) << lift;
  }
  const Eigen::Vector3d facing = body.Closest(hit.point + offset * hit.normal, 0.05).normal;
  ASSERT_LT((hit.normal + facing).norm(), 0.05);
  const double pushed = PushedDistance(body, inside);
  EXPECT_GT(pushed, 0);
  EXPECT_LT(pushed, 0.02);
}

// How far the apex of an upright triangle standing on the floor sinks under its own weight,
// m: only its two compressed edges hold it up.
double UprightTriangleSag(const ClothSettings& settings) {
  // The body only sets the floor (its lowest point, y = 0); it is too far away to touch.
  const core::Mesh sphere = UvSphere(1.0, 16, 24, Eigen::RowVector3d(5, 1, 0));
  const core::TriangleBvh body =
      *core::TriangleBvh::Build(sphere.positions, core::Triangulate(sphere.faces));
  // Starting within the floor's offset, so that the floor holds the base from the first step.
  const double base = 0.5 * settings.collision_offset;
  core::Positions garment(3, 3);
  garment << -0.05, base, 0, 0.05, base, 0, 0, base + 0.1, 0;
  const ClothModel model = OneTriangleModel(garment);
  ClothSolver solver(model, garment, PairLengths(garment, model.edges),
                     HingeAngles(garment, model.hinges), {}, body, settings);
  for (int step = 0; step < 5; ++step) solver.Step(body);
  const core::Positions& p = solver.positions();
  return 0.1 - (p(2, 1) - 0.5 * (p(0, 1) + p(1, 1)));
}

TEST(ClothSolverTest, CompressedEdgesTakeTheCompressionStiffness) {
  ClothSettings settings;
  const double sag = UprightTriangleSag(settings);
  EXPECT_GT(sag, 0);
  ClothSettings stiffer_stretch = settings;
  stiffer_stretch.stretch_stiffness *= 10;
  // The base edge, stretched as the legs spread, moves the apex a little.
  EXPECT_NEAR(UprightTriangleSag(stiffer_stretch), sag, 0.02 * sag);
  ClothSettings softer_compression = settings;
  softer_compression.compression_stiffness /= 10;
  EXPECT_NEAR(UprightTriangleSag(softer_compression), 10 * sag, 0.5 * sag);
}

TEST(ClothSolverTest, ACrushedTriangleKeepsTheAreaFloor) {
  // Compression all but free: only the area floor holds the apex up.
  ClothSettings settings;
  settings.compression_stiffness = 1e-3;
  ClothSettings no_floor = settings;
  no_floor.area_floor = 0;
  EXPECT_GT(UprightTriangleSag(no_floor), 0.09);
  // The base keeps its length, so the height is the area's share.
  EXPECT_NEAR(UprightTriangleSag(settings), 0.1 * (1 - settings.area_floor), 0.002);
}

}  // namespace
}  // namespace fitbase::workers
