#include "clothing/body_correspondence.h"

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "Eigen/Geometry"
#include "core/mesh.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::clothing {
namespace {

using core::StatusIs;

// The cube [-0.5, 0.5]^3 (m) as a body, with one component: a rigid lift along +y.
struct CubeBody {
  core::PcaBasis basis;
  core::Triangles triangles;
};

CubeBody MakeCube() {
  CubeBody cube;
  core::Positions corners(8, 3);
  for (int i = 0; i < 8; ++i) {
    corners.row(i) << (i & 1 ? 0.5 : -0.5), (i & 2 ? 0.5 : -0.5), (i & 4 ? 0.5 : -0.5);
  }
  cube.triangles.resize(12, 3);
  cube.triangles << 0, 2, 1, 1, 2, 3,  // z = -0.5
      4, 5, 6, 5, 7, 6,                // z = +0.5
      0, 1, 4, 1, 5, 4,                // y = -0.5
      2, 6, 3, 3, 6, 7,                // y = +0.5
      0, 4, 2, 2, 4, 6,                // x = -0.5
      1, 3, 5, 3, 7, 5;                // x = +0.5
  cube.basis.mean = Eigen::Map<const Eigen::VectorXd>(corners.data(), 24);
  cube.basis.components = Eigen::MatrixXd::Zero(24, 1);
  for (int i = 0; i < 8; ++i) cube.basis.components(3 * i + 1, 0) = 1 / std::sqrt(8.0);
  cube.basis.variances = Eigen::VectorXd::Constant(1, 1e-4);
  return cube;
}

TEST(BodyCorrespondenceTest, PushesOutOnlyTheVerticesTheCustomerBodyReaches) {
  const CubeBody cube = MakeCube();
  core::Positions garment(2, 3);
  garment << 0.1, 0.505, 0.2,  // 5 mm above the top face.
      0.6, 0.0, 0.1;           // 10 cm beside the +x face.
  const BodyCorrespondence correspondence =
      *BuildBodyCorrespondence({{&garment, Eigen::VectorXd::Zero(1)}}, cube.basis, cube.triangles,
                               core::Triangles(), 0.0025, 1);
  EXPECT_TRUE(ValidateBodyCorrespondence(correspondence, 2, 1).ok());

  Eigen::VectorXf lift(1);
  lift << static_cast<float>(0.02 * std::sqrt(8.0));  // The body rises by 2 cm.
  Eigen::VectorXf positions = Eigen::Map<const Eigen::VectorXd>(garment.data(), 6).cast<float>();
  CleanupScratch scratch;
  EXPECT_EQ(PushOutOfBody(correspondence, lift, scratch, positions.data()), 1);
  EXPECT_NEAR(positions(1), 0.5 + 0.02 + 0.0025, 1e-6);
  EXPECT_NEAR(positions(0), 0.1, 1e-7);
  EXPECT_NEAR(positions(2), 0.2, 1e-7);
  EXPECT_EQ(positions.tail<3>(), garment.row(1).transpose().cast<float>());

  // At the mean body nothing is inside: the fit is left as it is.
  positions = Eigen::Map<const Eigen::VectorXd>(garment.data(), 6).cast<float>();
  EXPECT_EQ(PushOutOfBody(correspondence, Eigen::VectorXf::Zero(1), scratch, positions.data()), 0);
}

// At the mean the vertex sits beside the +x face; in an example with the body lowered by 0.4 m
// it sits on the top face. A customer lowered by 0.395 m has the fitted vertex 1 mm inside the
// top: only the anchor from the second example sees that; the mean's anchor alone would push
// the vertex 20 cm sideways out of the +x face's plane.
BodyCorrespondence SlidingVertex(const CubeBody& cube) {
  core::Positions at_mean(1, 3), lowered(1, 3);
  at_mean << 0.503, 0.3, 0.0;
  lowered << 0.3, 0.103, 0.0;
  return *BuildBodyCorrespondence({{&at_mean, Eigen::VectorXd::Zero(1)},
                                   {&lowered, Eigen::VectorXd::Constant(1, -0.4 * std::sqrt(8.0))}},
                                  cube.basis, cube.triangles, core::Triangles(), 0.0025, 2);
}

// The fitted vertex on the customer lowered by 0.395 m, after the clean-up.
Eigen::VectorXf CleanUpOnTheLoweredCustomer(const BodyCorrespondence& correspondence) {
  Eigen::VectorXf positions = Eigen::Vector3f(0.3f, 0.104f, 0.0f);
  CleanupScratch scratch;
  const Eigen::VectorXf customer =
      Eigen::VectorXf::Constant(1, static_cast<float>(-0.395 * std::sqrt(8.0)));
  EXPECT_EQ(PushOutOfBody(correspondence, customer, scratch, positions.data()), 1);
  return positions;
}

TEST(BodyCorrespondenceTest, AnchorsFromExamplesFollowASlidingVertex) {
  const BodyCorrespondence correspondence = SlidingVertex(MakeCube());
  EXPECT_EQ(correspondence.anchors_per_vertex, 2);
  EXPECT_TRUE(ValidateBodyCorrespondence(correspondence, 1, 1).ok());
  const Eigen::VectorXf positions = CleanUpOnTheLoweredCustomer(correspondence);
  EXPECT_NEAR(positions(1), 0.105 + 0.0025, 1e-6);
  EXPECT_NEAR(positions(0), 0.3, 1e-6);
}

// The anchors are compared four at a time: the one that follows the vertex still wins from
// the second group, behind four that do not.
TEST(BodyCorrespondenceTest, FindsTheNearestAnchorBeyondTheFirstFour) {
  BodyCorrespondence correspondence = SlidingVertex(MakeCube());
  const Eigen::RowVector3i follows = correspondence.corners.row(1);
  const Eigen::RowVector3f follows_at = correspondence.barycentric.row(1);
  correspondence.anchors_per_vertex = 5;
  correspondence.corners = correspondence.corners.row(0).replicate(5, 1).eval();
  correspondence.barycentric = correspondence.barycentric.row(0).replicate(5, 1).eval();
  correspondence.corners.row(4) = follows;
  correspondence.barycentric.row(4) = follows_at;
  ASSERT_TRUE(ValidateBodyCorrespondence(correspondence, 1, 1).ok());
  const Eigen::VectorXf positions = CleanUpOnTheLoweredCustomer(correspondence);
  EXPECT_NEAR(positions(1), 0.105 + 0.0025, 1e-6);
  EXPECT_NEAR(positions(0), 0.3, 1e-6);
}

// Given the anchor rows (FollowBody's), the clean-up clears each vertex against its row's
// triangle, not its nearest anchor's: here the mean's anchor on the +x face, whose plane the
// vertex lies 20 cm behind.
TEST(BodyCorrespondenceTest, ClearsAgainstTheGivenAnchorRows) {
  const BodyCorrespondence correspondence = SlidingVertex(MakeCube());
  Eigen::VectorXf body;
  BodyPointsOfWeights(correspondence,
                      Eigen::VectorXf::Constant(1, static_cast<float>(-0.395 * std::sqrt(8.0))),
                      body);
  CleanupScratch scratch;
  for (const int32_t row : {0, 1}) {
    Eigen::VectorXf positions = Eigen::Vector3f(0.3f, 0.104f, 0.0f);
    const std::vector<int32_t> rows = {row};
    EXPECT_EQ(*PushOutOfBodyPoints(correspondence, body, rows, nullptr, scratch,
                                   positions.data()),
              1);
    if (row == 0) {
      EXPECT_NEAR(positions(0), 0.5 + 0.0025, 1e-6);
      EXPECT_NEAR(positions(1), 0.104, 1e-6);
    } else {
      EXPECT_NEAR(positions(0), 0.3, 1e-6);
      EXPECT_NEAR(positions(1), 0.105 + 0.0025, 1e-6);
    }
  }
}

// The cube lowered by 0.395 m (its top at y = 0.105) as a whole mesh: 3B floats and its
// triangles.
std::vector<float> LoweredCubeMesh() {
  std::vector<float> mesh(24);
  for (int i = 0; i < 8; ++i) {
    mesh[3 * i] = i & 1 ? 0.5f : -0.5f;
    mesh[3 * i + 1] = (i & 2 ? 0.5f : -0.5f) - 0.395f;
    mesh[3 * i + 2] = i & 4 ? 0.5f : -0.5f;
  }
  return mesh;
}

// The sliding vertex's correspondence on the customer lowered by 0.395 m: its body points, and
// the anchor row on the +x face (row 0) to clear against.
class DeepPushTest : public ::testing::Test {
 protected:
  DeepPushTest() { BodyPointsOfWeights(correspondence_, weights_, body_); }

  const CubeBody cube_ = MakeCube();
  const BodyCorrespondence correspondence_ = SlidingVertex(cube_);
  const Eigen::VectorXf weights_ =
      Eigen::VectorXf::Constant(1, static_cast<float>(-0.395 * std::sqrt(8.0)));
  Eigen::VectorXf body_;
  const std::vector<int32_t> plus_x_ = {0};
};

// Against the anchor on the +x face (row 0), every vertex below lies deep behind the anchor's
// plane, and without the mesh that plane pushes each out through the +x face. With the mesh,
// a vertex at the -x face, which looks away from the anchor's side, is cleared against that
// face instead: left alone 10 cm outside it, pushed out to the offset from 1 mm outside or
// 1 cm inside it. At the top (normal +y, not at an obtuse angle to +x) the plane's push
// stands, as without the mesh, for a vertex 1 mm inside; one 9.5 cm above, clear of the body,
// is pushed kDeepPush along the anchor's normal, no further.
TEST_F(DeepPushTest, AsksTheBodyMesh) {
  const std::vector<float> mesh = LoweredCubeMesh();
  const BodyMesh cube_mesh{.positions = mesh, .triangles = &cube_.triangles};
  CleanupScratch scratch;
  const auto clean = [&](Eigen::Vector3f at, const BodyMesh* with) {
    Eigen::VectorXf positions = at;
    const int64_t moved =
        *PushOutOfBodyPoints(correspondence_, body_, plus_x_, with, scratch, positions.data());
    EXPECT_EQ(moved, positions == Eigen::VectorXf(at) ? 0 : 1);
    return Eigen::Vector3f(positions);
  };

  const Eigen::Vector3f beside(-0.6f, -0.4f, 0.0f);
  EXPECT_NEAR(clean(beside, nullptr).x(), 0.5 + 0.0025, 1e-6);  // Through the body.
  EXPECT_EQ(clean(beside, &cube_mesh), beside);
  EXPECT_EQ(scratch.deep_checks, 1);
  for (const float x : {-0.501f, -0.49f}) {
    const Eigen::Vector3f out = clean(Eigen::Vector3f(x, -0.4f, 0.0f), &cube_mesh);
    EXPECT_NEAR(out.x(), -0.5 - 0.0025, 1e-6);
    EXPECT_NEAR(out.y(), -0.4, 1e-6);
  }

  const Eigen::Vector3f in_top(0.3f, 0.104f, 0.0f);
  EXPECT_NEAR(clean(in_top, &cube_mesh).x(), 0.5 + 0.0025, 1e-6);
  const Eigen::Vector3f above(0.3f, 0.2f, 0.0f);
  const Eigen::Vector3f pulled = clean(above, &cube_mesh);
  EXPECT_NEAR(pulled.x(), 0.3 + kDeepPush, 1e-6);
  EXPECT_NEAR(pulled.y(), 0.2, 1e-6);
  EXPECT_EQ(scratch.deep_checks, 1);

  // 2 cm behind the plane is not deep: the mesh is not asked.
  const Eigen::Vector3f shallow(0.48f, 0.2f, 0.0f);
  EXPECT_NEAR(clean(shallow, &cube_mesh).x(), 0.5 + 0.0025, 1e-6);
  EXPECT_EQ(scratch.deep_checks, 0);
}

// The tree the scratch keeps is refitted to each mesh: a fit after one on another body answers
// as a fresh scratch does, and a mesh of another topology gets a tree of its own.
TEST_F(DeepPushTest, RefitsTheTreeToEachMesh) {
  const std::vector<float> lowered = LoweredCubeMesh();
  std::vector<float> wider = lowered;
  for (size_t i = 0; i < wider.size(); i += 3) wider[i] *= 1.1f;  // The -x face at -0.55.
  const Eigen::Vector3f in_left(-0.49f, -0.4f, 0.0f);
  const auto clean = [&](const std::vector<float>& mesh, const core::Triangles& triangles,
                         CleanupScratch& scratch) {
    Eigen::VectorXf positions = in_left;
    const BodyMesh with{.positions = mesh, .triangles = &triangles};
    EXPECT_TRUE(
        PushOutOfBodyPoints(correspondence_, body_, plus_x_, &with, scratch, positions.data())
            .ok());
    return Eigen::Vector3f(positions);
  };
  CleanupScratch shared;
  EXPECT_NEAR(clean(lowered, cube_.triangles, shared).x(), -0.5025, 1e-6);
  CleanupScratch fresh;
  const Eigen::Vector3f refitted = clean(wider, cube_.triangles, shared);
  EXPECT_EQ(refitted, clean(wider, cube_.triangles, fresh));
  EXPECT_NEAR(refitted.x(), -0.5525, 1e-6);
  // The same cube with its triangles' corners rotated: another topology, the same surface.
  core::Triangles rotated = cube_.triangles;
  for (Eigen::Index t = 0; t < rotated.rows(); ++t) {
    rotated.row(t) << cube_.triangles(t, 1), cube_.triangles(t, 2), cube_.triangles(t, 0);
  }
  EXPECT_NEAR(clean(lowered, rotated, shared).x(), -0.5025, 1e-6);
}

// Without the customer's mesh, the body of the weights is made from the avatar basis when a
// deep push needs it, and answers as that body given as a mesh does.
TEST_F(DeepPushTest, MakesTheBodyOfTheWeights) {
  const std::vector<float> mesh = LoweredCubeMesh();
  const BodyMesh given{.positions = mesh, .triangles = &cube_.triangles};
  const BodyMesh made{.avatar = &cube_.basis, .weights = &weights_, .triangles = &cube_.triangles};
  for (const float x : {-0.6f, -0.49f, 0.3f}) {
    Eigen::VectorXf from_given = Eigen::Vector3f(x, x < 0 ? -0.4f : 0.2f, 0.0f);
    Eigen::VectorXf from_made = from_given;
    CleanupScratch scratch;
    ASSERT_TRUE(
        PushOutOfBodyPoints(correspondence_, body_, plus_x_, &given, scratch, from_given.data())
            .ok());
    ASSERT_TRUE(
        PushOutOfBodyPoints(correspondence_, body_, plus_x_, &made, scratch, from_made.data())
            .ok());
    EXPECT_TRUE(from_made.isApprox(from_given, 1e-6f)) << x;
  }
  const Eigen::VectorXf two = Eigen::VectorXf::Zero(2);
  const BodyMesh mismatched{.avatar = &cube_.basis, .weights = &two, .triangles = &cube_.triangles};
  Eigen::VectorXf positions = Eigen::Vector3f(-0.49f, -0.4f, 0.0f);
  CleanupScratch scratch;
  EXPECT_THAT(
      PushOutOfBodyPoints(correspondence_, body_, plus_x_, &mismatched, scratch, positions.data()),
      StatusIs(absl::StatusCode::kInvalidArgument, "does not take 2 weights"));
}

TEST_F(DeepPushTest, RejectsABadMesh) {
  CleanupScratch scratch;
  const auto clean = [&](const std::vector<float>& mesh, const core::Triangles* triangles) {
    Eigen::VectorXf positions = Eigen::Vector3f(0.3f, 0.2f, 0.0f);
    const BodyMesh with{.positions = mesh, .triangles = triangles};
    return PushOutOfBodyPoints(correspondence_, body_, plus_x_, &with, scratch, positions.data())
        .status();
  };
  std::vector<float> mesh = LoweredCubeMesh();
  EXPECT_TRUE(clean(mesh, &cube_.triangles).ok());
  EXPECT_THAT(clean(mesh, nullptr), StatusIs(absl::StatusCode::kInvalidArgument, "no triangles"));
  core::Triangles out_of_range = cube_.triangles;
  out_of_range(3, 1) = 8;
  EXPECT_THAT(clean(mesh, &out_of_range),
              StatusIs(absl::StatusCode::kInvalidArgument, "triangle 3 corner 1"));
  mesh[7] = std::numeric_limits<float>::infinity();
  EXPECT_THAT(clean(mesh, &cube_.triangles),
              StatusIs(absl::StatusCode::kInvalidArgument, "body vertex 2 has a non-finite"));
  mesh.pop_back();
  EXPECT_THAT(clean(mesh, &cube_.triangles),
              StatusIs(absl::StatusCode::kInvalidArgument, "not a multiple of 3"));
}

TEST(BodyCorrespondenceTest, KeepsOnlyTheBodyVerticesItNeeds) {
  const CubeBody cube = MakeCube();
  core::Positions garment(1, 3);
  garment << 0.1, 0.505, 0.2;
  const BodyCorrespondence correspondence =
      *BuildBodyCorrespondence({{&garment, Eigen::VectorXd::Zero(1)}}, cube.basis, cube.triangles,
                               core::Triangles(), 0.0025, 1);
  EXPECT_EQ(correspondence.body_vertices.size(), 3u);
  EXPECT_EQ(correspondence.body_components.rows(), 9);
  EXPECT_NEAR(correspondence.barycentric.sum(), 1.0f, 1e-6);
}

TEST(BodyCorrespondenceTest, RejectsBadInput) {
  const CubeBody cube = MakeCube();
  core::Positions garment(1, 3);
  garment << 0.1, std::nan(""), 0.2;
  const std::vector<CorrespondenceExample> examples = {{&garment, Eigen::VectorXd::Zero(1)}};
  EXPECT_THAT(
      BuildBodyCorrespondence(examples, cube.basis, cube.triangles, core::Triangles(), 0.0025, 1),
      StatusIs(absl::StatusCode::kInvalidArgument, "not finite"));
  garment(0, 1) = 0.6;
  EXPECT_THAT(
      BuildBodyCorrespondence(examples, cube.basis, cube.triangles, core::Triangles(), 0, 1),
      StatusIs(absl::StatusCode::kInvalidArgument, "offset"));
  EXPECT_THAT(
      BuildBodyCorrespondence(examples, cube.basis, cube.triangles, core::Triangles(), 0.0025, 0),
      StatusIs(absl::StatusCode::kInvalidArgument, "anchors per vertex"));
  const BodyCorrespondence correspondence =
      *BuildBodyCorrespondence(examples, cube.basis, cube.triangles, core::Triangles(), 0.0025, 1);
  EXPECT_THAT(ValidateBodyCorrespondence(correspondence, 5, 1),
              StatusIs(absl::StatusCode::kInvalidArgument, "the garment has 5 vertices"));
  EXPECT_THAT(ValidateBodyCorrespondence(correspondence, 1, 3),
              StatusIs(absl::StatusCode::kInvalidArgument, "expected 3"));
}

// A flat body patch in y = 0: the square [-1, 1]^2 (vertices 0-3) around the square
// [-0.1, 0.1]^2 (4-7) around a centre vertex (8) that component 0 raises, a bump. Triangles
// face +y.
struct Tent {
  core::PcaBasis basis;
  core::Triangles triangles;
};

Tent MakeTent() {
  Tent tent;
  core::Positions points(9, 3);
  points << -1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1,  //
      -0.1, 0, -0.1, 0.1, 0, -0.1, 0.1, 0, 0.1, -0.1, 0, 0.1, 0, 0, 0;
  tent.triangles.resize(12, 3);
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    tent.triangles.row(i) << 8, 4 + i, 4 + j;
    tent.triangles.row(4 + 2 * i) << i, j, 4 + j;
    tent.triangles.row(5 + 2 * i) << i, 4 + j, 4 + i;
  }
  for (Eigen::Index t = 0; t < tent.triangles.rows(); ++t) {
    if (core::TriangleCross(points, tent.triangles, t).y() < 0) {
      std::swap(tent.triangles(t, 1), tent.triangles(t, 2));
    }
  }
  tent.basis.mean = Eigen::Map<const Eigen::VectorXd>(points.data(), 27);
  tent.basis.components = Eigen::MatrixXd::Zero(27, 1);
  tent.basis.components(3 * 8 + 1, 0) = 1;
  tent.basis.variances = Eigen::VectorXd::Constant(1, 1e-4);
  return tent;
}

// Height (y) of the garment triangle's plane over the point (x, z) = (0, 0).
float HeightAtCentre(const Eigen::VectorXf& positions) {
  const Eigen::Vector3f a = positions.segment<3>(0);
  const Eigen::Vector3f b = positions.segment<3>(3);
  const Eigen::Vector3f c = positions.segment<3>(6);
  const Eigen::Vector3f n = (b - a).cross(c - a);
  return a.y() + (n.x() * a.x() + n.z() * a.z()) / n.y();
}

// One garment triangle with 0.8 m edges, 5 mm over the patch in the example. A customer whose
// bump rises 2 cm pierces it between its corners, which lie over the outer, unmoved part: the
// vertices' own anchors see nothing to push, the guard of the bump's vertex lifts the triangle.
TEST(BodyCorrespondenceTest, GuardLiftsATriangleOffABumpBetweenItsCorners) {
  const Tent tent = MakeTent();
  core::Positions garment(3, 3);
  garment << -0.4, 0.005, -0.4, 0.0, 0.005, 0.5, 0.4, 0.005, -0.4;
  core::Triangles garment_triangles(1, 3);
  garment_triangles << 0, 1, 2;  // Facing -y: the build orients the guard itself.
  const std::vector<CorrespondenceExample> examples = {{&garment, Eigen::VectorXd::Zero(1)}};
  const BodyCorrespondence guarded = *BuildBodyCorrespondence(
      examples, tent.basis, tent.triangles, garment_triangles, 0.0025, 1);
  ASSERT_TRUE(ValidateBodyCorrespondence(guarded, 3, 1).ok());
  // The centre and the inner square lie under the triangle; the outer corners are beyond reach.
  std::vector<int32_t> guarded_points;
  for (int32_t b : guarded.guard_body) guarded_points.push_back(guarded.body_vertices[b]);
  EXPECT_THAT(guarded_points, ::testing::ElementsAre(4, 5, 6, 7, 8));
  EXPECT_EQ(guarded.smoothing_iterations, kSmoothingIterations);
  EXPECT_THAT(guarded.neighbors, ::testing::ElementsAre(1, 2, 0, 2, 0, 1));

  const Eigen::VectorXf bump = Eigen::VectorXf::Constant(1, 0.02f);
  const Eigen::VectorXf fit = Eigen::Map<const Eigen::VectorXd>(garment.data(), 9).cast<float>();
  CleanupScratch scratch;
  Eigen::VectorXf positions = fit;
  const BodyCorrespondence unguarded = *BuildBodyCorrespondence(
      examples, tent.basis, tent.triangles, core::Triangles(), 0.0025, 1);
  EXPECT_EQ(PushOutOfBody(unguarded, bump, scratch, positions.data()), 0);
  EXPECT_EQ(positions, fit);

  EXPECT_EQ(PushOutOfBody(guarded, bump, scratch, positions.data()), 3);
  // At least the offset over the bump; the smoothing keeps each corner's share of the push, so
  // the triangle may rise a little more.
  EXPECT_GE(HeightAtCentre(positions), 0.02 + 0.0025 - 1e-6);
  EXPECT_LT(HeightAtCentre(positions), 0.02 + 0.0025 + 0.005);
  for (int v = 0; v < 3; ++v) {
    EXPECT_NEAR(positions(3 * v), fit(3 * v), 1e-7);
    EXPECT_NEAR(positions(3 * v + 2), fit(3 * v + 2), 1e-7);
  }
  // Warm scratch, body back flat: nothing inside, nothing moves.
  positions = fit;
  EXPECT_EQ(PushOutOfBody(guarded, Eigen::VectorXf::Zero(1), scratch, positions.data()), 0);
  EXPECT_EQ(positions, fit);
}

// A strip of 2 x 5 garment vertices 1 cm over the plane y = 0, but vertex 2 of the first row
// 1 cm under it. Vertex by vertex only that one moves, leaving a spike; smoothed, its push
// fades over its neighbours, each moved less than it and more than the vertices beyond.
TEST(BodyCorrespondenceTest, SmoothingFadesAPushOverTheNeighbours) {
  BodyCorrespondence c;
  c.offset = 0.0025;
  c.body_vertices = {0, 1, 2};
  c.body_mean.resize(9);
  c.body_mean << -1, 0, -1, -1, 0, 2, 2, 0, -1;  // Normal +y.
  c.body_components = Eigen::MatrixXf::Zero(9, 1);
  c.corners = decltype(c.corners)::Zero(10, 3);
  c.corners.col(1).setConstant(1);
  c.corners.col(2).setConstant(2);
  c.barycentric = decltype(c.barycentric)::Constant(10, 3, 1.0f / 3);
  Eigen::VectorXf fit(30);
  for (int v = 0; v < 10; ++v) fit.segment<3>(3 * v) << 0.1f * (v % 5), 0.01f, 0.1f * (v / 5);
  fit(3 * 2 + 1) = -0.01f;
  core::Triangles strip(8, 3);
  strip << 0, 5, 1, 1, 5, 6, 1, 6, 2, 2, 6, 7, 2, 7, 3, 3, 7, 8, 3, 8, 4, 4, 8, 9;
  const Eigen::VectorXf w = Eigen::VectorXf::Zero(1);
  CleanupScratch scratch;

  Eigen::VectorXf spike = fit;
  ASSERT_TRUE(ValidateBodyCorrespondence(c, 10, 1).ok());
  EXPECT_EQ(PushOutOfBody(c, w, scratch, spike.data()), 1);
  EXPECT_NEAR(spike(3 * 2 + 1), 0.0025, 1e-7);

  ASSERT_TRUE(SetGarmentNeighbors(strip, c).ok());
  c.smoothing_iterations = 4;
  ASSERT_TRUE(ValidateBodyCorrespondence(c, 10, 1).ok());
  Eigen::VectorXf smooth = fit;
  EXPECT_EQ(PushOutOfBody(c, w, scratch, smooth.data()), 10);
  const Eigen::VectorXf lift = smooth - fit;
  EXPECT_NEAR(smooth(3 * 2 + 1), 0.0025, 1e-6);
  for (int v : {1, 3, 6, 7}) {  // The pushed vertex's neighbours.
    EXPECT_GT(lift(3 * v + 1), 0) << v;
    EXPECT_LT(lift(3 * v + 1), lift(3 * 2 + 1)) << v;
  }
  EXPECT_LT(lift(3 * 0 + 1), lift(3 * 1 + 1));
  EXPECT_LT(lift(3 * 4 + 1), lift(3 * 3 + 1));
  EXPECT_LT(lift(3 * 9 + 1), lift(3 * 8 + 1));
  // A second fit from the same scratch gives the same bytes.
  Eigen::VectorXf again = fit;
  PushOutOfBody(c, w, scratch, again.data());
  EXPECT_EQ(again, smooth);
}

TEST(BodyCorrespondenceTest, RejectsBadGuardsAndNeighbours) {
  const Tent tent = MakeTent();
  core::Positions garment(3, 3);
  garment << -0.4, 0.005, -0.4, 0.0, 0.005, 0.5, 0.4, 0.005, -0.4;
  const std::vector<CorrespondenceExample> examples = {{&garment, Eigen::VectorXd::Zero(1)}};
  core::Triangles garment_triangles(1, 3);
  garment_triangles << 0, 1, 3;
  EXPECT_THAT(BuildBodyCorrespondence(examples, tent.basis, tent.triangles, garment_triangles,
                                      0.0025, 1),
              StatusIs(absl::StatusCode::kInvalidArgument, "garment triangle corner outside"));
  garment_triangles << 0, 1, 2;
  const BodyCorrespondence good = *BuildBodyCorrespondence(examples, tent.basis, tent.triangles,
                                                           garment_triangles, 0.0025, 1);
  BodyCorrespondence bad = good;
  bad.guard_body.push_back(0);
  EXPECT_THAT(ValidateBodyCorrespondence(bad, 3, 1),
              StatusIs(absl::StatusCode::kInvalidArgument, "6 guard body points for 5"));
  bad = good;
  bad.guard_body[0] = static_cast<int32_t>(good.body_vertices.size());
  EXPECT_THAT(ValidateBodyCorrespondence(bad, 3, 1),
              StatusIs(absl::StatusCode::kInvalidArgument, "guard body point"));
  bad = good;
  bad.guard_triangles(0, 2) = 3;
  EXPECT_THAT(ValidateBodyCorrespondence(bad, 3, 1),
              StatusIs(absl::StatusCode::kInvalidArgument, "guard triangle corner"));
  bad = good;
  bad.smoothing_iterations = kMaxSmoothingIterations + 1;
  EXPECT_THAT(ValidateBodyCorrespondence(bad, 3, 1),
              StatusIs(absl::StatusCode::kInvalidArgument, "smoothing iterations"));
  bad = good;
  bad.neighbor_offsets.clear();
  bad.neighbors.clear();
  EXPECT_THAT(ValidateBodyCorrespondence(bad, 3, 1),
              StatusIs(absl::StatusCode::kInvalidArgument, "no garment neighbour lists"));
  bad = good;
  bad.neighbors[0] = 3;
  EXPECT_THAT(ValidateBodyCorrespondence(bad, 3, 1),
              StatusIs(absl::StatusCode::kInvalidArgument, "neighbour 3 outside"));
  bad = good;
  bad.neighbor_offsets.pop_back();
  EXPECT_THAT(ValidateBodyCorrespondence(bad, 3, 1),
              StatusIs(absl::StatusCode::kInvalidArgument, "neighbour lists do not match"));
  garment_triangles << 0, 1, 5;
  EXPECT_THAT(SetGarmentNeighbors(garment_triangles, bad),
              StatusIs(absl::StatusCode::kInvalidArgument, "garment triangle 0"));
}

// Two body triangles side by side in the plane y = 0 (normal +y), and a garment triangle 1 cm
// above them whose vertex 0 is anchored on the first and vertices 1 and 2 on the second.
BodyCorrespondence TwoTriangles() {
  BodyCorrespondence c;
  c.offset = 0.0025;
  c.body_vertices = {0, 1, 2, 3, 4, 5};
  c.body_mean.resize(18);
  c.body_mean << 0, 0, 0, 0, 0, 1, 1, 0, 0,  // First triangle.
      2, 0, 0, 2, 0, 1, 3, 0, 0;             // Second.
  c.body_components = Eigen::MatrixXf::Zero(18, 1);
  c.corners.resize(3, 3);
  c.corners << 0, 1, 2, 3, 4, 5, 3, 4, 5;
  c.barycentric.resize(3, 3);
  c.barycentric << 0.4f, 0.3f, 0.3f, 0.4f, 0.3f, 0.3f, 0.2f, 0.2f, 0.6f;
  return c;
}

TEST(BodyCorrespondenceTest, FollowBodyCarriesTheNormalOffsetAndSmoothsItOverTheGarment) {
  BodyCorrespondence c = TwoTriangles();
  Eigen::VectorXf of_weights;
  BodyPointsOfWeights(c, Eigen::VectorXf::Zero(1), of_weights);
  // The first triangle 6 mm higher and 5 cm along x; the second where it was.
  Eigen::VectorXf mesh = of_weights;
  for (int i = 0; i < 3; ++i) {
    mesh(3 * i) += 0.05f;
    mesh(3 * i + 1) += 0.006f;
  }
  const Eigen::VectorXf garment =
      (Eigen::VectorXf(9) << 0.3f, 0.01f, 0.3f, 2.3f, 0.01f, 0.3f, 2.5f, 0.01f, 0.5f).finished();
  CleanupScratch scratch;
  // Without neighbour lists: vertex 0 rises with its triangle, only along the normal.
  Eigen::VectorXf moved = garment;
  FollowBody(c, of_weights, mesh, scratch, moved.data());
  EXPECT_NEAR(moved(0), 0.3f, 1e-6);
  EXPECT_NEAR(moved(1), 0.016f, 1e-6);
  EXPECT_NEAR(moved(4), 0.01f, 1e-6);
  EXPECT_NEAR(moved(7), 0.01f, 1e-6);
  EXPECT_EQ(scratch.anchor_rows, (std::vector<int32_t>{0, 1, 2}));
  // With them: the 6 mm are shared over the triangle (each vertex averages itself and its two
  // neighbours), 2 mm each after the first round and after every later one.
  core::Triangles garment_triangles(1, 3);
  garment_triangles << 0, 1, 2;
  ASSERT_TRUE(SetGarmentNeighbors(garment_triangles, c).ok());
  moved = garment;
  FollowBody(c, of_weights, mesh, scratch, moved.data());
  for (int v = 0; v < 3; ++v) {
    EXPECT_NEAR(moved(3 * v + 1), 0.012f, 1e-6) << v;
    EXPECT_NEAR(moved(3 * v), garment(3 * v), 1e-6) << v;
  }
}

TEST(BodyCorrespondenceTest, GatherBodyPointsTakesTheUsedVerticesOfAMesh) {
  BodyCorrespondence c = TwoTriangles();
  c.body_vertices = {1, 3, 4, 6, 7, 9};
  std::vector<float> mesh(30);
  for (int i = 0; i < 30; ++i) mesh[i] = static_cast<float>(i);
  Eigen::VectorXf points;
  ASSERT_TRUE(GatherBodyPoints(c, mesh, points).ok());
  ASSERT_EQ(points.size(), 18);
  EXPECT_EQ(points(0), 3.0f);
  EXPECT_EQ(points(17), 29.0f);
  mesh.resize(27);
  EXPECT_THAT(GatherBodyPoints(c, mesh, points),
              StatusIs(absl::StatusCode::kInvalidArgument, "uses vertex 9"));
}

}  // namespace
}  // namespace fitbase::clothing
