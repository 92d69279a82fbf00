#include "clothing/body_correspondence.h"

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "Eigen/Geometry"
#include "absl/algorithm/container.h"
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
  EXPECT_EQ(*PushOutOfBody(correspondence, lift, scratch, positions.data()), 1);
  EXPECT_NEAR(positions(1), 0.5 + 0.02 + 0.0025, 1e-6);
  EXPECT_NEAR(positions(0), 0.1, 1e-7);
  EXPECT_NEAR(positions(2), 0.2, 1e-7);
  EXPECT_EQ(positions.tail<3>(), garment.row(1).transpose().cast<float>());

  // At the mean body nothing is inside: the fit is left as it is.
  positions = Eigen::Map<const Eigen::VectorXd>(garment.data(), 6).cast<float>();
  EXPECT_EQ(*PushOutOfBody(correspondence, Eigen::VectorXf::Zero(1), scratch, positions.data()), 0);
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
  EXPECT_EQ(*PushOutOfBody(correspondence, customer, scratch, positions.data()), 1);
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
    EXPECT_EQ(*PushOutOfBodyPoints(correspondence, body, rows, scratch, positions.data()), 1);
    if (row == 0) {
      EXPECT_NEAR(positions(0), 0.5 + 0.0025, 1e-6);
      EXPECT_NEAR(positions(1), 0.104, 1e-6);
    } else {
      EXPECT_NEAR(positions(0), 0.3, 1e-6);
      EXPECT_NEAR(positions(1), 0.105 + 0.0025, 1e-6);
    }
  }
}

// The sliding vertex's correspondence with every cube vertex as a body point (row i: vertex
// i), as if the garment covered the whole cube: its body_triangles are the cube's.
BodyCorrespondence OverTheWholeCube(const CubeBody& cube) {
  BodyCorrespondence correspondence = SlidingVertex(cube);
  for (Eigen::Index i = 0; i < correspondence.corners.size(); ++i) {
    correspondence.corners.data()[i] =
        correspondence.body_vertices[static_cast<size_t>(correspondence.corners.data()[i])];
  }
  correspondence.body_vertices = {0, 1, 2, 3, 4, 5, 6, 7};
  correspondence.body_mean = cube.basis.mean.cast<float>();
  correspondence.body_components = cube.basis.components.cast<float>();
  correspondence.body_triangles = cube.triangles;
  return correspondence;
}

// The correspondence without its body_triangles, as in a basis built before them.
BodyCorrespondence WithoutBodyTriangles(BodyCorrespondence correspondence) {
  correspondence.body_triangles.resize(0, 3);
  return correspondence;
}

// That correspondence on the customer lowered by 0.395 m (its top at y = 0.105): its body
// points, and the anchor row on the +x face (row 0) to clear against.
class DeepPushTest : public ::testing::Test {
 protected:
  DeepPushTest() { BodyPointsOfWeights(correspondence_, weights_, body_); }

  // The vertex at `at` after the clean-up against row 0 (one vertex moved, or none).
  Eigen::Vector3f Clean(const BodyCorrespondence& correspondence, const Eigen::VectorXf& body,
                        const Eigen::Vector3f& at, CleanupScratch& scratch) const {
    Eigen::VectorXf positions = at;
    const int64_t moved =
        *PushOutOfBodyPoints(correspondence, body, plus_x_, scratch, positions.data());
    EXPECT_EQ(moved, positions == Eigen::VectorXf(at) ? 0 : 1);
    return Eigen::Vector3f(positions);
  }

  const CubeBody cube_ = MakeCube();
  const BodyCorrespondence correspondence_ = OverTheWholeCube(cube_);
  const Eigen::VectorXf weights_ =
      Eigen::VectorXf::Constant(1, static_cast<float>(-0.395 * std::sqrt(8.0)));
  Eigen::VectorXf body_;
  const std::vector<int32_t> plus_x_ = {0};
};

// Against the anchor on the +x face (row 0), every vertex below lies deep behind the anchor's
// plane, and without the body triangles that plane pushes each out through the +x face. With
// them, a vertex at the -x face, which looks away from the anchor's side, is cleared against
// that face instead: left alone 10 cm outside it, pushed out to the offset from 1 mm outside
// or 1 cm inside it. At the top (normal +y, not at an obtuse angle to +x) the plane's push
// stands, as without them, for a vertex 1 mm inside; one 9.5 cm above, clear of the body, is
// pushed kDeepPush along the anchor's normal, no further.
TEST_F(DeepPushTest, AsksTheBodyUnderTheGarment) {
  ASSERT_EQ(correspondence_.corners(0, 0), 3);  // Row 0 lies on the +x face.
  const BodyCorrespondence unasked = WithoutBodyTriangles(correspondence_);
  CleanupScratch scratch;
  const auto clean = [&](const Eigen::Vector3f& at) {
    return Clean(correspondence_, body_, at, scratch);
  };

  const Eigen::Vector3f beside(-0.6f, -0.4f, 0.0f);
  EXPECT_NEAR(Clean(unasked, body_, beside, scratch).x(), 0.5 + 0.0025, 1e-6);  // Through it.
  EXPECT_EQ(scratch.deep_checks, 0);
  EXPECT_EQ(clean(beside), beside);
  EXPECT_EQ(scratch.deep_checks, 1);
  for (const float x : {-0.501f, -0.49f}) {
    const Eigen::Vector3f out = clean(Eigen::Vector3f(x, -0.4f, 0.0f));
    EXPECT_NEAR(out.x(), -0.5 - 0.0025, 1e-6);
    EXPECT_NEAR(out.y(), -0.4, 1e-6);
  }

  EXPECT_NEAR(clean(Eigen::Vector3f(0.3f, 0.104f, 0.0f)).x(), 0.5 + 0.0025, 1e-6);
  const Eigen::Vector3f pulled = clean(Eigen::Vector3f(0.3f, 0.2f, 0.0f));
  EXPECT_NEAR(pulled.x(), 0.3 + kDeepPush, 1e-6);
  EXPECT_NEAR(pulled.y(), 0.2, 1e-6);
  EXPECT_EQ(scratch.deep_checks, 1);

  // 2 cm behind the plane is not deep: the body is not asked.
  EXPECT_NEAR(clean(Eigen::Vector3f(0.48f, 0.2f, 0.0f)).x(), 0.5 + 0.0025, 1e-6);
  EXPECT_EQ(scratch.deep_checks, 0);
}

// Weights far outside any body overflow its points; a deep push then finds the body under the
// garment not finite and the clean-up says so rather than searching it. Without a deep push
// nothing is searched.
TEST_F(DeepPushTest, RefusesABodyThatIsNotFinite) {
  Eigen::VectorXf overflowed = body_;
  overflowed(0) = std::numeric_limits<float>::infinity();  // Vertex 0, not of row 0's triangle.
  CleanupScratch scratch;
  Eigen::VectorXf positions = Eigen::Vector3f(-0.6f, -0.4f, 0.0f);
  EXPECT_THAT(
      PushOutOfBodyPoints(correspondence_, overflowed, plus_x_, scratch, positions.data()),
      StatusIs(absl::StatusCode::kInvalidArgument, "body point under the garment is not finite"));
  positions = Eigen::Vector3f(0.48f, 0.2f, 0.0f);
  EXPECT_TRUE(
      PushOutOfBodyPoints(correspondence_, overflowed, plus_x_, scratch, positions.data()).ok());
}

// Only the body under the garment is asked. The sliding vertex's own correspondence, as built,
// has body triangles at the +x face, the top and the front, and none at the -x face: a vertex
// 1 cm inside that face finds the nearest of them about 60 cm away with the body on the far
// side, so it gets the plane's push, as without them.
TEST_F(DeepPushTest, AsksOnlyTheBodyUnderTheGarment) {
  const BodyCorrespondence sliding = SlidingVertex(cube_);
  ASSERT_GT(sliding.body_triangles.rows(), 0);
  EXPECT_FALSE(absl::c_linear_search(sliding.body_vertices, 0));
  Eigen::VectorXf body;
  BodyPointsOfWeights(sliding, weights_, body);
  CleanupScratch scratch;
  const Eigen::Vector3f in_left(-0.49f, -0.4f, 0.0f);
  const Eigen::Vector3f asked = Clean(sliding, body, in_left, scratch);
  EXPECT_EQ(scratch.deep_checks, 1);
  EXPECT_EQ(asked, Clean(WithoutBodyTriangles(sliding), body, in_left, scratch));
  EXPECT_NEAR(asked.x(), 0.5 + 0.0025, 1e-6);
}

// The tree the scratch keeps is refitted to each body: a fit after one on another body answers
// as a fresh scratch does, and another garment's body triangles get a tree of their own.
TEST_F(DeepPushTest, RefitsTheTreeToEachBody) {
  Eigen::VectorXf wider = body_;
  for (Eigen::Index i = 0; i < wider.size(); i += 3) wider(i) *= 1.1f;  // The -x face at -0.55.
  const Eigen::Vector3f in_left(-0.49f, -0.4f, 0.0f);
  CleanupScratch shared;
  EXPECT_NEAR(Clean(correspondence_, body_, in_left, shared).x(), -0.5025, 1e-6);
  CleanupScratch fresh;
  const Eigen::Vector3f refitted = Clean(correspondence_, wider, in_left, shared);
  EXPECT_EQ(refitted, Clean(correspondence_, wider, in_left, fresh));
  EXPECT_NEAR(refitted.x(), -0.5525, 1e-6);
  // The same cube with its triangles' corners rotated: another topology, the same surface.
  BodyCorrespondence rotated = correspondence_;
  for (Eigen::Index t = 0; t < rotated.body_triangles.rows(); ++t) {
    rotated.body_triangles.row(t) << cube_.triangles(t, 1), cube_.triangles(t, 2),
        cube_.triangles(t, 0);
  }
  EXPECT_NEAR(Clean(rotated, body_, in_left, shared).x(), -0.5025, 1e-6);
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
  // The one triangle under the garment, its corners as rows of the body points.
  ASSERT_EQ(correspondence.body_triangles.rows(), 1);
  EXPECT_EQ(correspondence.body_triangles.minCoeff(), 0);
  EXPECT_EQ(correspondence.body_triangles.maxCoeff(), 2);
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
  for (const int32_t corner : {-1, 3}) {
    BodyCorrespondence bad = correspondence;
    bad.body_triangles(0, 1) = corner;
    EXPECT_THAT(
        ValidateBodyCorrespondence(bad, 1, 1),
        StatusIs(absl::StatusCode::kInvalidArgument, "body triangle corner outside [0, 3)"));
  }
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
  EXPECT_EQ(*PushOutOfBody(unguarded, bump, scratch, positions.data()), 0);
  EXPECT_EQ(positions, fit);

  EXPECT_EQ(*PushOutOfBody(guarded, bump, scratch, positions.data()), 3);
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
  EXPECT_EQ(*PushOutOfBody(guarded, Eigen::VectorXf::Zero(1), scratch, positions.data()), 0);
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
  EXPECT_EQ(*PushOutOfBody(c, w, scratch, spike.data()), 1);
  EXPECT_NEAR(spike(3 * 2 + 1), 0.0025, 1e-7);

  ASSERT_TRUE(SetGarmentNeighbors(strip, c).ok());
  c.smoothing_iterations = 4;
  ASSERT_TRUE(ValidateBodyCorrespondence(c, 10, 1).ok());
  Eigen::VectorXf smooth = fit;
  EXPECT_EQ(*PushOutOfBody(c, w, scratch, smooth.data()), 10);
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
  ASSERT_TRUE(PushOutOfBody(c, w, scratch, again.data()).ok());
  EXPECT_EQ(again, smooth);
  // Each round carries the push one ring of neighbours further: vertex 2, then 1, 3, 6 and 7,
  // then 0, 4, 5 and 8, then 9.
  for (const auto& [rounds, moved] : std::vector<std::pair<int, int>>{{1, 5}, {2, 9}, {3, 10}}) {
    c.smoothing_iterations = rounds;
    Eigen::VectorXf ringed = fit;
    EXPECT_EQ(*PushOutOfBody(c, w, scratch, ringed.data()), moved) << rounds;
    EXPECT_NEAR(ringed(3 * 2 + 1), 0.0025, 1e-6) << rounds;
  }
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
