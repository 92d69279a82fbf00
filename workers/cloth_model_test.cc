#include "workers/cloth_model.h"

#include <algorithm>
#include <cmath>

#include "body/body_measurements.h"
#include "body/body_model.h"
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

// `part` appended to `mesh` as a piece of its own.
void Append(const core::Mesh& part, core::Mesh* mesh) {
  const int32_t offset = static_cast<int32_t>(mesh->positions.rows());
  mesh->positions.conservativeResize(offset + part.positions.rows(), 3);
  mesh->positions.bottomRows(part.positions.rows()) = part.positions;
  mesh->faces.sizes.insert(mesh->faces.sizes.end(), part.faces.sizes.begin(),
                           part.faces.sizes.end());
  for (int32_t index : part.faces.indices) mesh->faces.indices.push_back(offset + index);
}

// `tube` without the faces of its column in front (+z): a jacket open down its front.
core::Mesh OpenInFront(core::Mesh tube, int segments) {
  core::PolygonFaces faces;
  const int front = 3 * segments / 4;  // Tube's column s sits at angle 2 pi s / segments.
  for (size_t f = 0; f < tube.faces.sizes.size(); ++f) {
    if (static_cast<int>(f) % segments == front) continue;
    faces.sizes.push_back(4);
    faces.indices.insert(faces.indices.end(), tube.faces.indices.begin() + 4 * f,
                         tube.faces.indices.begin() + 4 * (f + 1));
  }
  tube.faces = faces;
  return tube;
}

// A body of only the landmarks FindSupports reads: the crotch at the origin, the underbust
// 0.4 m and the neck girth 0.6 m above it.
core::Positions LandmarksOnly() {
  using body::BodyLandmarks;
  core::Positions body = core::Positions::Zero(body::kBodyVertexCount, 3);
  body.row(BodyLandmarks::kCrotch) << 0, 0, 0.02;
  body.row(BodyLandmarks::kLeftUnderbust) << 0.1, 0.4, 0.1;
  body.row(BodyLandmarks::kNeckFront) << 0, 0.6, 0.06;
  body.row(BodyLandmarks::kNeckBack) << 0, 0.6, -0.04;
  return body;
}

TEST(FindSupportsTest, OnlyOpeningsRoundTheTorsoOrTheNeckHoldTheGarmentUp) {
  core::Positions body = LandmarksOnly();
  // Pieces in the order of their lowest vertex: trousers, a button on them, a jacket open in
  // front, a shirt's collar.
  core::Mesh garment;
  Append(Tube(0.16, -0.3, 0.2, 4, 16), &garment);
  core::Mesh button = Tube(0.01, 0.25, 0.26, 1, 6);
  button.positions.rowwise() += Eigen::RowVector3d(0.05, 0, 0.17);
  Append(button, &garment);
  Append(OpenInFront(Tube(0.19, 0.3, 0.62, 4, 16), 16), &garment);
  Append(Tube(0.07, 0.5, 0.62, 2, 16), &garment);
  auto model = BuildClothModel(garment.positions, garment.faces, 0.2);
  ASSERT_TRUE(model.ok()) << model.status();
  // The trousers' hem and waistband, the button's two rims, the jacket's one loop (front
  // edges, hem and neckline), the collar's two rims.
  ASSERT_EQ(model->openings.size(), 7u);
  auto top_of_piece = [&](int32_t piece) {
    for (size_t o = 0; o < model->openings.size(); ++o) {
      const Opening& opening = model->openings[o];
      if (opening.piece == piece && opening.highest_of_piece) return static_cast<int32_t>(o);
    }
    return int32_t{-1};
  };
  const Opening& jacket = model->openings[top_of_piece(2)];
  // Both a waistband's and a collar's place: only the ring decides.
  ASSERT_GT(jacket.mean_height, 0.3);
  ASSERT_LT(jacket.mean_height, 0.62);

  auto supports = FindSupports(*model, garment.positions, body);
  ASSERT_TRUE(supports.ok()) << supports.status();
  std::vector<int32_t> band = model->openings[top_of_piece(0)].edges;
  std::sort(band.begin(), band.end());
  EXPECT_EQ(supports->waistband_edges, band);
  EXPECT_EQ(supports->collars, std::vector<int32_t>{top_of_piece(3)});

  // With the underbust lower, the jacket's loop is above it: no collar either.
  body(body::BodyLandmarks::kLeftUnderbust, 1) = 0.28;
  supports = FindSupports(*model, garment.positions, body);
  ASSERT_TRUE(supports.ok());
  EXPECT_EQ(supports->waistband_edges, band);
  EXPECT_EQ(supports->collars, std::vector<int32_t>{top_of_piece(3)});
}

TEST(FindSupportsTest, ABibOverallHangsFromItsStrapsNotFromAButtonhole) {
  const core::Positions body = LandmarksOnly();
  // A tube whose top edge is 0.62 m high in front and behind (bib and back) and 0.2 m at the
  // sides, with a buttonhole near the top of the bib: one face of its second row from the top,
  // in front (+z).
  constexpr int kRows = 8, kSegments = 16;
  core::Mesh overall = Tube(0.16, 0.0, 0.62, kRows, kSegments);
  for (Eigen::Index v = 0; v < overall.positions.rows(); ++v) {
    const double front_or_back = std::abs(overall.positions(v, 2)) / 0.16;
    overall.positions(v, 1) *= (0.2 + 0.42 * front_or_back) / 0.62;
  }
  const int hole = (kRows - 2) * kSegments + 3 * kSegments / 4;
  overall.faces.sizes.erase(overall.faces.sizes.begin() + hole);
  overall.faces.indices.erase(overall.faces.indices.begin() + 4 * hole,
                              overall.faces.indices.begin() + 4 * (hole + 1));
  auto model = BuildClothModel(overall.positions, overall.faces, 0.2);
  ASSERT_TRUE(model.ok()) << model.status();
  // The hem, the buttonhole and the top edge, in the order of their lowest vertex index.
  ASSERT_EQ(model->openings.size(), 3u);
  const Opening& buttonhole = model->openings[1];
  const Opening& top = model->openings[2];
  ASSERT_EQ(buttonhole.vertices.size(), 4u);
  // The buttonhole is higher on average; the top edge has the highest vertex.
  ASSERT_GT(buttonhole.mean_height, top.mean_height);
  EXPECT_TRUE(top.highest_of_piece);
  EXPECT_FALSE(buttonhole.highest_of_piece);

  auto supports = FindSupports(*model, overall.positions, body);
  ASSERT_TRUE(supports.ok()) << supports.status();
  // It goes round the neck but reaches below the underbust: straps, not a collar.
  EXPECT_EQ(supports->straps, std::vector<int32_t>{2});
  EXPECT_TRUE(supports->IsStrap(2));
  EXPECT_FALSE(supports->IsStrap(1));
  EXPECT_TRUE(supports->collars.empty());
  EXPECT_TRUE(supports->waistband_edges.empty());
}

TEST(FindSupportsTest, RejectsABodyOrGarmentOfAnotherVertexCount) {
  const core::Mesh tube = Tube(0.2, 0.0, 0.4, 2, 6);
  auto model = BuildClothModel(tube.positions, tube.faces, 0.2);
  ASSERT_TRUE(model.ok());
  const core::Positions body = core::Positions::Zero(body::kBodyVertexCount, 3);
  EXPECT_EQ(FindSupports(*model, tube.positions, body.topRows(100)).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(FindSupports(*model, tube.positions.topRows(6), body).status().code(),
            absl::StatusCode::kInvalidArgument);
}

// A body avatar of three upright limbs, ellipsoids 6 cm in radius and 1 m long round the
// origin's height (legs at x = +-0.15, an arm at x = 0.6), in its first vertices, and the crotch
// landmark 0.1 m high.
core::Mesh ThreeLimbs() {
  core::Mesh limbs;
  for (double x : {0.15, -0.15, 0.6}) {
    core::Mesh limb = UvSphere(1.0, 24, 32);
    limb.positions = limb.positions * Eigen::Vector3d(0.06, 0.5, 0.06).asDiagonal();
    limb.positions.rowwise() += Eigen::RowVector3d(x, 0, 0);
    Append(limb, &limbs);
  }
  const Eigen::Index used = limbs.positions.rows();
  EXPECT_LT(used, body::BodyLandmarks::kCrotch);
  limbs.positions.conservativeResize(body::kBodyVertexCount, 3);
  limbs.positions.bottomRows(body::kBodyVertexCount - used).setZero();
  limbs.positions.row(body::BodyLandmarks::kCrotch) << 0, 0.1, 0;
  return limbs;
}

TEST(FindCuffsTest, DeclaredEndsThatRingOneLimbAreCuffsASkirtsHemIsNot) {
  const core::Mesh limbs = ThreeLimbs();
  const core::Triangles triangles = core::Triangulate(limbs.faces);
  // A trouser leg round the left leg, a skirt round both, a sleeve round the arm; each a
  // piece whose bottom ring is its end and whose top ring its highest opening.
  core::Mesh garment;
  std::vector<body::BodyRegion> regions;
  auto add = [&](core::Mesh part, double x, body::BodyRegion region) {
    part.positions.rowwise() += Eigen::RowVector3d(x, 0, 0);
    Append(part, &garment);
    regions.insert(regions.end(), static_cast<size_t>(part.positions.rows()), region);
  };
  add(Tube(0.1, -0.3, 0.2, 4, 24), 0.15, body::BodyRegion::kLegs);
  add(Tube(0.3, -0.2, 0.1, 4, 32), 0.0, body::BodyRegion::kLegs);
  add(Tube(0.1, -0.3, 0.2, 4, 24), 0.6, body::BodyRegion::kArms);
  auto model = BuildClothModel(garment.positions, garment.faces, 0.2);
  ASSERT_TRUE(model.ok()) << model.status();
  std::vector<int32_t> ends(3, -1);
  for (size_t o = 0; o < model->openings.size(); ++o) {
    const Opening& opening = model->openings[o];
    if (!opening.highest_of_piece) ends[opening.piece] = static_cast<int32_t>(o);
  }
  ASSERT_EQ(std::count(ends.begin(), ends.end(), -1), 0);
  auto openings = [&](CuffDeclaration declared) {
    auto cuffs =
        FindCuffs(*model, garment.positions, regions, limbs.positions, triangles, declared);
    EXPECT_TRUE(cuffs.ok()) << cuffs.status();
    return cuffs.value_or(std::vector<int32_t>{});
  };
  EXPECT_TRUE(openings({}).empty());
  EXPECT_EQ(openings({.sleeves = false, .legs = true}), std::vector<int32_t>{ends[0]});
  EXPECT_EQ(openings({.sleeves = true, .legs = false}), std::vector<int32_t>{ends[2]});
  std::vector<int32_t> both = {ends[0], ends[2]};
  std::sort(both.begin(), both.end());
  EXPECT_EQ(openings({.sleeves = true, .legs = true}), both);

  // A leg's end is below the crotch: a T-shirt's hem over the hips covers the thighs' region.
  core::Positions low_crotch = limbs.positions;
  low_crotch(body::BodyLandmarks::kCrotch, 1) = -0.35;
  auto cuffs = FindCuffs(*model, garment.positions, regions, low_crotch, triangles,
                         {.sleeves = true, .legs = true});
  ASSERT_TRUE(cuffs.ok()) << cuffs.status();
  EXPECT_EQ(*cuffs, std::vector<int32_t>{ends[2]});
  EXPECT_EQ(FindCuffs(*model, garment.positions, regions, limbs.positions.topRows(100), triangles,
                      {.sleeves = true, .legs = true})
                .status()
                .code(),
            absl::StatusCode::kInvalidArgument);

  regions.pop_back();
  EXPECT_EQ(FindCuffs(*model, garment.positions, regions, limbs.positions, triangles,
                      {.sleeves = true, .legs = true})
                .status()
                .code(),
            absl::StatusCode::kInvalidArgument);
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
