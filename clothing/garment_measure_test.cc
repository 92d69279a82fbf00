#include "clothing/garment_measure.h"

#include <cmath>
#include <numbers>

#include "gtest/gtest.h"

namespace fitbase::clothing {
namespace {

// An open tube along y (no caps, like a sleeve): `segments` around, `rings` of them from
// y = 0 to y = 0.3, radius r. Faces wind outward.
struct Tube {
  core::Positions positions;
  core::Triangles triangles;
};
Tube MakeTube(double r, int segments, int rings, double arc = 2 * std::numbers::pi) {
  const bool closed = arc >= 2 * std::numbers::pi;
  const int around = closed ? segments : segments + 1;
  Tube tube;
  tube.positions.resize(static_cast<Eigen::Index>(around) * rings, 3);
  for (int k = 0; k < rings; ++k) {
    for (int i = 0; i < around; ++i) {
      const double t = arc * i / segments;
      tube.positions.row(k * around + i) << r * std::cos(t), 0.3 * k / (rings - 1),
          r * std::sin(t);
    }
  }
  std::vector<std::array<int32_t, 3>> faces;
  for (int k = 0; k + 1 < rings; ++k) {
    for (int i = 0; i < segments; ++i) {
      const int32_t a = k * around + i;
      const int32_t b = k * around + (i + 1) % around;
      faces.push_back({a, a + around, b});
      faces.push_back({b, a + around, b + around});
    }
  }
  tube.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int c = 0; c < 3; ++c) tube.triangles(static_cast<Eigen::Index>(f), c) = faces[f][c];
  }
  return tube;
}

// Rest lengths: the fitted edge lengths divided by `stretch` (a garment stretched evenly).
TriangleEdgeLengths RestOf(const Tube& tube, double stretch) {
  TriangleEdgeLengths rest(tube.triangles.rows(), 3);
  for (Eigen::Index t = 0; t < tube.triangles.rows(); ++t) {
    for (int c = 0; c < 3; ++c) {
      rest(t, c) = (tube.positions.row(tube.triangles(t, c)) -
                    tube.positions.row(tube.triangles(t, (c + 1) % 3)))
                       .norm() /
                   stretch;
    }
  }
  return rest;
}

body::GirthPlace Horizontal(double y) {
  return {Eigen::Vector3d(0, y, 0), Eigen::Vector3d::UnitY(), Eigen::Vector3d(0, y, 0)};
}

TEST(GarmentGirthAtTest, EvenlyStretchedTubeGivesItsRestGirthAndStretch) {
  const Tube tube = MakeTube(0.15, 64, 7);
  const double polygon = 64 * 2 * 0.15 * std::sin(std::numbers::pi / 64);
  const auto girth = GarmentGirthAt(tube.positions, tube.triangles, RestOf(tube, 1.1),
                                    Horizontal(0.13));
  ASSERT_TRUE(girth.has_value());
  EXPECT_NEAR(girth->fitted, polygon, 1e-9);
  EXPECT_NEAR(girth->rest, polygon / 1.1, 1e-9);
  EXPECT_NEAR(girth->stretch, 0.1, 1e-9);
}

TEST(GarmentGirthAtTest, ThePlaneBeyondTheGarmentOrAnOpenSectionHasNoGirth) {
  const Tube tube = MakeTube(0.15, 32, 4);
  EXPECT_FALSE(GarmentGirthAt(tube.positions, tube.triangles, RestOf(tube, 1), Horizontal(0.5))
                   .has_value());
  // Three quarters of a tube: the section does not go round the body.
  const Tube open = MakeTube(0.15, 24, 4, 1.5 * std::numbers::pi);
  EXPECT_FALSE(GarmentGirthAt(open.positions, open.triangles, RestOf(open, 1), Horizontal(0.1))
                   .has_value());
}

TEST(GarmentGirthAtTest, TheInnerOfTwoLayersHoldsTheBody) {
  // A waistband (r = 0.14) inside a top hanging over it (r = 0.2), in one mesh.
  const Tube inner = MakeTube(0.14, 48, 4);
  const Tube outer = MakeTube(0.20, 48, 4);
  Tube both;
  both.positions.resize(inner.positions.rows() + outer.positions.rows(), 3);
  both.positions << inner.positions, outer.positions;
  both.triangles.resize(inner.triangles.rows() + outer.triangles.rows(), 3);
  both.triangles << inner.triangles,
      (outer.triangles.array() + static_cast<int32_t>(inner.positions.rows())).matrix();
  const auto girth =
      GarmentGirthAt(both.positions, both.triangles, RestOf(both, 1.0), Horizontal(0.1));
  ASSERT_TRUE(girth.has_value());
  EXPECT_NEAR(girth->rest, 48 * 2 * 0.14 * std::sin(std::numbers::pi / 48), 1e-9);
}

TEST(VertexStretchPercentTest, EvenStretchIsTheSameAtEveryVertexAndGatheringIsNegative) {
  const Tube tube = MakeTube(0.15, 16, 3);
  const Eigen::VectorXf stretched =
      VertexStretchPercent(tube.positions, tube.triangles, RestOf(tube, 1.25));
  ASSERT_EQ(stretched.size(), tube.positions.rows());
  for (Eigen::Index v = 0; v < stretched.size(); ++v) EXPECT_NEAR(stretched(v), 25.0, 1e-4);
  const Eigen::VectorXf gathered =
      VertexStretchPercent(tube.positions, tube.triangles, RestOf(tube, 0.8));
  EXPECT_NEAR(gathered(0), -20.0, 1e-4);
}

TEST(VertexEaseMmTest, SignedDistanceToTheBodyInMillimetres) {
  // The body: a closed tube of radius 0.1 would need caps; a capped box is simpler.
  core::Positions box(8, 3);
  box << -0.1, -0.1, -0.1, 0.1, -0.1, -0.1, 0.1, 0.1, -0.1, -0.1, 0.1, -0.1, -0.1, -0.1, 0.1,
      0.1, -0.1, 0.1, 0.1, 0.1, 0.1, -0.1, 0.1, 0.1;
  core::Triangles faces(12, 3);
  faces << 0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 2, 3, 7, 2, 7, 6, 1, 2, 6, 1, 6,
      5, 0, 4, 7, 0, 7, 3;
  auto body = core::TriangleBvh::Build(box, faces);
  ASSERT_TRUE(body.ok()) << body.status();
  core::Positions garment(3, 3);
  garment << 0, 0.13, 0, 0.095, 0, 0, 5, 0, 0;
  const Eigen::VectorXf ease = VertexEaseMm(garment, *body, 200);
  EXPECT_NEAR(ease(0), 30.0, 1e-3);
  EXPECT_NEAR(ease(1), -5.0, 1e-3);
  EXPECT_EQ(ease(2), 200.0f);  // Nothing within 200 mm.
}

}  // namespace
}  // namespace fitbase::clothing
