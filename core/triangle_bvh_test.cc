#include "core/triangle_bvh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <utility>
#include <vector>

#include "Eigen/Geometry"
#include "core/random.h"
#include "core/test_support.h"
#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kTolerance = 1e-12;

struct TestMesh {
  Positions positions;
  Triangles triangles;
};

// The cube [0, 1]^3 as six counter-clockwise quads split by core::Triangulate; vertex i sits at
// (i & 1, (i >> 1) & 1, (i >> 2) & 1).
TestMesh UnitCube() {
  TestMesh cube;
  cube.positions.resize(8, 3);
  for (int i = 0; i < 8; ++i) cube.positions.row(i) << (i & 1), ((i >> 1) & 1), ((i >> 2) & 1);
  cube.triangles = Triangulate(PolygonFaces{
      .sizes = {4, 4, 4, 4, 4, 4},
      .indices = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5}});
  return cube;
}

// A regular tetrahedron centred on the origin: every dihedral angle is 70.5 degrees, so near an
// edge or a corner one face's normal alone gives the wrong side.
TestMesh Tetrahedron() {
  TestMesh tetra;
  tetra.positions.resize(4, 3);
  tetra.positions << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
  tetra.triangles.resize(4, 3);
  tetra.triangles << 0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2;
  return tetra;
}

// The icosahedron subdivided `levels` times, projected on the sphere of `radius` at the origin.
TestMesh Icosphere(int levels, double radius) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> vertices = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                                           {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                                           {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  std::vector<std::array<int32_t, 3>> faces = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (Eigen::Vector3d& v : vertices) v.normalize();
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int32_t, int32_t>, int32_t> midpoints;
    auto midpoint = [&](int32_t a, int32_t b) {
      const auto key = std::minmax(a, b);
      auto [it, inserted] = midpoints.emplace(key, static_cast<int32_t>(vertices.size()));
      if (inserted) vertices.push_back((vertices[a] + vertices[b]).normalized());
      return it->second;
    };
    std::vector<std::array<int32_t, 3>> finer;
    for (const auto& [a, b, c] : faces) {
      const int32_t ab = midpoint(a, b);
      const int32_t bc = midpoint(b, c);
      const int32_t ca = midpoint(c, a);
      finer.insert(finer.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    faces = std::move(finer);
  }
  TestMesh sphere;
  sphere.positions.resize(static_cast<Eigen::Index>(vertices.size()), 3);
  for (size_t v = 0; v < vertices.size(); ++v) {
    sphere.positions.row(static_cast<Eigen::Index>(v)) = radius * vertices[v].transpose();
  }
  sphere.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (size_t t = 0; t < faces.size(); ++t) {
    sphere.triangles.row(static_cast<Eigen::Index>(t)) << faces[t][0], faces[t][1], faces[t][2];
  }
  return sphere;
}

Eigen::Vector3d Corner(const TestMesh& mesh, Eigen::Index t, int k) {
  return mesh.positions.row(mesh.triangles(t, k)).transpose();
}

Eigen::Vector3d FaceNormal(const TestMesh& mesh, Eigen::Index t) {
  const Eigen::Vector3d a = Corner(mesh, t, 0);
  return (Corner(mesh, t, 1) - a).cross(Corner(mesh, t, 2) - a).normalized();
}

// Six times the enclosed volume: positive when the triangles face outwards.
double SignedVolume6(const TestMesh& mesh) {
  double volume = 0.0;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    volume += Corner(mesh, t, 0).dot(Corner(mesh, t, 1).cross(Corner(mesh, t, 2)));
  }
  return volume;
}

TestMesh Flipped(TestMesh mesh) {
  mesh.triangles.col(1).swap(mesh.triangles.col(2));
  return mesh;
}

double SegmentDistance(const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                       const Eigen::Vector3d& b) {
  const double length2 = (b - a).squaredNorm();
  const double s = length2 > 0.0 ? std::clamp((q - a).dot(b - a) / length2, 0.0, 1.0) : 0.0;
  return (q - (a + s * (b - a))).norm();
}

// Distance to the nearest triangle by a different route than the tree's: the nearest of the
// three sides, or the projection on the plane when it falls inside.
double BruteForceDistance(const TestMesh& mesh, const Eigen::Vector3d& q) {
  double best = kInfinity;
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const Eigen::Vector3d a = Corner(mesh, t, 0);
    const Eigen::Vector3d b = Corner(mesh, t, 1);
    const Eigen::Vector3d c = Corner(mesh, t, 2);
    best = std::min(
        {best, SegmentDistance(q, a, b), SegmentDistance(q, b, c), SegmentDistance(q, c, a)});
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    if (cross.squaredNorm() == 0.0) continue;
    const Eigen::Vector3d n = cross.normalized();
    const Eigen::Vector3d projected = q - n.dot(q - a) * n;
    if ((c - b).cross(projected - b).dot(n) >= 0 && (a - c).cross(projected - c).dot(n) >= 0 &&
        (b - a).cross(projected - a).dot(n) >= 0) {
      best = std::min(best, std::abs(n.dot(q - a)));
    }
  }
  return best;
}

TriangleBvh BuildOrDie(const TestMesh& mesh) {
  auto bvh = TriangleBvh::Build(mesh.positions, mesh.triangles);
  EXPECT_TRUE(bvh.ok()) << bvh.status();
  return *std::move(bvh);
}

// The answer is consistent with itself: `point` is the barycentric combination of the named
// triangle's corners, at |signed_distance| from the query, and the normal is a unit vector.
void ExpectConsistent(const TestMesh& mesh, const Eigen::Vector3d& q, const SurfacePoint& hit) {
  ASSERT_TRUE(hit.found);
  ASSERT_GE(hit.triangle, 0);
  ASSERT_LT(hit.triangle, mesh.triangles.rows());
  EXPECT_NEAR(hit.barycentric.sum(), 1.0, kTolerance);
  EXPECT_GE(hit.barycentric.minCoeff(), -kTolerance);
  const Eigen::Vector3d combined = hit.barycentric[0] * Corner(mesh, hit.triangle, 0) +
                                   hit.barycentric[1] * Corner(mesh, hit.triangle, 1) +
                                   hit.barycentric[2] * Corner(mesh, hit.triangle, 2);
  EXPECT_LT((combined - hit.point).norm(), kTolerance);
  EXPECT_NEAR((q - hit.point).norm(), std::abs(hit.signed_distance), kTolerance);
  EXPECT_NEAR(hit.normal.norm(), 1.0, kTolerance);
}

void ExpectSameBits(const SurfacePoint& a, const SurfacePoint& b) {
  EXPECT_EQ(a.found, b.found);
  EXPECT_EQ(a.triangle, b.triangle);
  EXPECT_EQ(a.barycentric, b.barycentric);
  EXPECT_EQ(a.point, b.point);
  EXPECT_EQ(a.normal, b.normal);
  EXPECT_EQ(a.signed_distance, b.signed_distance);
}

Eigen::Vector3d UniformPoint(Random& random, double lo, double hi) {
  const double x = random.Uniform(lo, hi);
  const double y = random.Uniform(lo, hi);
  const double z = random.Uniform(lo, hi);
  return Eigen::Vector3d(x, y, z);
}

TEST(TriangleBvhTest, TestMeshesFaceOutwards) {
  EXPECT_NEAR(SignedVolume6(UnitCube()), 6.0, kTolerance);
  EXPECT_GT(SignedVolume6(Tetrahedron()), 0.0);
  EXPECT_GT(SignedVolume6(Icosphere(3, 1.0)), 0.0);
}

struct CubeCase {
  Eigen::Vector3d query;
  double signed_distance;
  Eigen::Vector3d point;
  Eigen::Vector3d normal;
};

TEST(TriangleBvhTest, CubeDistancesToFacesEdgesAndCorners) {
  const TestMesh cube = UnitCube();
  const TriangleBvh bvh = BuildOrDie(cube);
  const double r2 = 1.0 / std::sqrt(2.0);
  const double r3 = 1.0 / std::sqrt(3.0);
  const std::vector<CubeCase> cases = {
      // Faces, from outside and inside, off and on the quads' diagonals.
      {{0.3, 0.6, 1.3}, 0.3, {0.3, 0.6, 1.0}, {0, 0, 1}},
      {{0.5, 0.5, 1.3}, 0.3, {0.5, 0.5, 1.0}, {0, 0, 1}},
      {{-0.25, 0.7, 0.2}, 0.25, {0.0, 0.7, 0.2}, {-1, 0, 0}},
      {{0.4, 0.5, 0.8}, -0.2, {0.4, 0.5, 1.0}, {0, 0, 1}},
      {{0.5, 0.05, 0.4}, -0.05, {0.5, 0.0, 0.4}, {0, -1, 0}},
      // Edges: the sign and normal come from the two faces' sum.
      {{1.2, 0.5, 1.2}, std::sqrt(0.08), {1.0, 0.5, 1.0}, {r2, 0, r2}},
      {{-0.3, 0.25, -0.4}, 0.5, {0.0, 0.25, 0.0}, {-r2, 0, -r2}},
      {{0.9, 1.1, -0.05}, std::sqrt(0.0125), {0.9, 1.0, 0.0}, {0, r2, -r2}},
      // Corners: the angle-weighted normal of three right angles is the diagonal.
      {{1.1, 1.2, 1.3}, std::sqrt(0.14), {1, 1, 1}, {r3, r3, r3}},
      {{-0.2, -0.2, -0.2}, std::sqrt(0.12), {0, 0, 0}, {-r3, -r3, -r3}},
      {{1.3, -0.4, 1.2}, std::sqrt(0.29), {1, 0, 1}, {r3, -r3, r3}},
  };
  for (const CubeCase& c : cases) {
    SCOPED_TRACE(::testing::Message() << "query " << c.query.transpose());
    const SurfacePoint hit = bvh.Closest(c.query, kInfinity);
    ExpectConsistent(cube, c.query, hit);
    EXPECT_NEAR(hit.signed_distance, c.signed_distance, kTolerance);
    EXPECT_LT((hit.point - c.point).norm(), kTolerance);
    EXPECT_LT((hit.normal - c.normal).norm(), kTolerance);
  }
  // The centre is equally near all six faces; only the distance is defined.
  EXPECT_NEAR(bvh.Closest(Eigen::Vector3d(0.5, 0.5, 0.5), kInfinity).signed_distance, -0.5,
              kTolerance);
}

TEST(TriangleBvhTest, CubeSignsMatchContainmentOnARandomCloud) {
  const TestMesh cube = UnitCube();
  const TriangleBvh bvh = BuildOrDie(cube);
  Random random(1, 0);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d q = UniformPoint(random, -0.5, 1.5);
    const SurfacePoint hit = bvh.Closest(q, kInfinity);
    ExpectConsistent(cube, q, hit);
    const double brute = BruteForceDistance(cube, q);
    ASSERT_NEAR(std::abs(hit.signed_distance), brute, kTolerance) << q.transpose();
    const bool inside = q.minCoeff() > 0.0 && q.maxCoeff() < 1.0;
    ASSERT_EQ(hit.signed_distance < 0.0, inside) << q.transpose();
  }
}

// Points whose offset from an edge or a corner lies inside the feature's normal cone but at
// more than 90 degrees from one adjacent face's normal: only the pseudo-normal signs them
// right, on a convex feature (outside) and, with the mesh turned inside out, a concave one.
TEST(TriangleBvhTest, EdgeAndCornerPseudoNormalsSignSharpFeatures) {
  const TestMesh tetra = Tetrahedron();
  const TestMesh inverted = Flipped(tetra);
  const TriangleBvh outer = BuildOrDie(tetra);
  const TriangleBvh inner = BuildOrDie(inverted);
  const double offset = 0.1;
  const std::vector<std::pair<double, double>> edge_weights = {
      {1.0, 0.05}, {0.05, 1.0}, {1.0, 1.0}, {0.3, 1.0}};
  int face_normal_would_fail = 0;
  // Each undirected edge once: side k of triangle t, seen from the face on its left.
  for (Eigen::Index t = 0; t < 4; ++t) {
    for (int k = 0; k < 3; ++k) {
      const int32_t u = tetra.triangles(t, k);
      const int32_t v = tetra.triangles(t, (k + 1) % 3);
      if (u > v) continue;
      Eigen::Index other = -1;
      for (Eigen::Index s = 0; s < 4; ++s) {
        if (s == t) continue;
        for (int j = 0; j < 3; ++j) {
          if (tetra.triangles(s, j) == v && tetra.triangles(s, (j + 1) % 3) == u) other = s;
        }
      }
      ASSERT_GE(other, 0);
      const Eigen::Vector3d n1 = FaceNormal(tetra, t);
      const Eigen::Vector3d n2 = FaceNormal(tetra, other);
      const Eigen::Vector3d edge_normal = (n1 + n2).normalized();
      const Eigen::Vector3d on_edge =
          0.7 * tetra.positions.row(u).transpose() + 0.3 * tetra.positions.row(v).transpose();
      for (const auto& [w1, w2] : edge_weights) {
        const Eigen::Vector3d direction = (w1 * n1 + w2 * n2).normalized();
        if (std::min(direction.dot(n1), direction.dot(n2)) < 0.0) ++face_normal_would_fail;
        const Eigen::Vector3d q = on_edge + offset * direction;
        SCOPED_TRACE(::testing::Message() << "edge " << u << "-" << v << " q " << q.transpose());
        const SurfacePoint out = outer.Closest(q, kInfinity);
        ExpectConsistent(tetra, q, out);
        EXPECT_NEAR(out.signed_distance, offset, kTolerance);
        EXPECT_LT((out.point - on_edge).norm(), kTolerance);
        EXPECT_LT((out.normal - edge_normal).norm(), kTolerance);
        const SurfacePoint in = inner.Closest(q, kInfinity);
        EXPECT_NEAR(in.signed_distance, -offset, kTolerance);
        EXPECT_LT((in.normal + edge_normal).norm(), kTolerance);
      }
    }
  }
  const std::vector<Eigen::Vector3d> corner_weights = {
      {1.0, 0.02, 0.02}, {0.02, 1.0, 0.02}, {0.02, 0.02, 1.0}, {1.0, 1.0, 0.05}};
  for (int32_t vertex = 0; vertex < 4; ++vertex) {
    std::vector<Eigen::Vector3d> normals;
    for (Eigen::Index t = 0; t < 4; ++t) {
      if ((tetra.triangles.row(t).array() == vertex).any()) normals.push_back(FaceNormal(tetra, t));
    }
    ASSERT_EQ(normals.size(), 3u);
    const Eigen::Vector3d corner = tetra.positions.row(vertex).transpose();
    // By symmetry the angle-weighted normal points away from the centre.
    const Eigen::Vector3d vertex_normal = corner.normalized();
    for (const Eigen::Vector3d& w : corner_weights) {
      const Eigen::Vector3d direction =
          (w[0] * normals[0] + w[1] * normals[1] + w[2] * normals[2]).normalized();
      double worst = kInfinity;
      for (const Eigen::Vector3d& n : normals) worst = std::min(worst, direction.dot(n));
      if (worst < 0.0) ++face_normal_would_fail;
      const Eigen::Vector3d q = corner + offset * direction;
      SCOPED_TRACE(::testing::Message() << "corner " << vertex << " q " << q.transpose());
      const SurfacePoint out = outer.Closest(q, kInfinity);
      ExpectConsistent(tetra, q, out);
      EXPECT_NEAR(out.signed_distance, offset, kTolerance);
      EXPECT_LT((out.point - corner).norm(), kTolerance);
      EXPECT_LT((out.normal - vertex_normal).norm(), kTolerance);
      const SurfacePoint in = inner.Closest(q, kInfinity);
      EXPECT_NEAR(in.signed_distance, -offset, kTolerance);
      EXPECT_LT((in.normal + vertex_normal).norm(), kTolerance);
    }
  }
  // Most of these points would get the wrong sign from some adjacent face's own normal.
  EXPECT_GE(face_normal_would_fail, 30);
}

TEST(TriangleBvhTest, OpenBoundaryTakesTheFaceNormal) {
  TestMesh triangle;
  triangle.positions.resize(3, 3);
  triangle.positions << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  triangle.triangles.resize(1, 3);
  triangle.triangles << 0, 1, 2;
  const TriangleBvh bvh = BuildOrDie(triangle);
  const SurfacePoint beyond_edge = bvh.Closest(Eigen::Vector3d(0.5, -0.5, 0.1), kInfinity);
  EXPECT_NEAR(beyond_edge.signed_distance, std::sqrt(0.26), kTolerance);
  EXPECT_EQ(beyond_edge.normal, Eigen::Vector3d(0, 0, 1));
  const SurfacePoint below_corner = bvh.Closest(Eigen::Vector3d(-0.3, -0.4, -1.2), kInfinity);
  EXPECT_NEAR(below_corner.signed_distance, -1.3, kTolerance);
  EXPECT_EQ(below_corner.barycentric, Eigen::Vector3d(1, 0, 0));
}

TEST(TriangleBvhTest, SphereMatchesBruteForceAndContainment) {
  const TestMesh sphere = Icosphere(3, 1.0);
  ASSERT_EQ(sphere.triangles.rows(), 1280);
  const TriangleBvh bvh = BuildOrDie(sphere);
  // Every face plane is at least this far from the centre, so nearer points are inside.
  double inradius = kInfinity;
  for (Eigen::Index t = 0; t < sphere.triangles.rows(); ++t) {
    inradius = std::min(inradius, FaceNormal(sphere, t).dot(Corner(sphere, t, 0)));
  }
  Random random(2, 0);
  int inside = 0;
  int outside = 0;
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d q = UniformPoint(random, -1.6, 1.6);
    const SurfacePoint hit = bvh.Closest(q, kInfinity);
    ExpectConsistent(sphere, q, hit);
    ASSERT_NEAR(std::abs(hit.signed_distance), BruteForceDistance(sphere, q), kTolerance)
        << q.transpose();
    if (q.norm() > 1.0) {
      ++outside;
      ASSERT_GT(hit.signed_distance, 0.0) << q.transpose();
    } else if (q.norm() < inradius) {
      ++inside;
      ASSERT_LT(hit.signed_distance, 0.0) << q.transpose();
    }
  }
  // The ball fills 13% of the sampled cube.
  EXPECT_GT(inside, 250);
  EXPECT_GT(outside, 1500);
}

TEST(TriangleBvhTest, MaxDistanceBoundsTheSearch) {
  const TestMesh sphere = Icosphere(2, 0.5);
  const TriangleBvh bvh = BuildOrDie(sphere);
  Random random(3, 0);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d q = UniformPoint(random, -1.0, 1.0);
    const SurfacePoint unbounded = bvh.Closest(q, kInfinity);
    const double distance = std::abs(unbounded.signed_distance);
    const SurfacePoint short_of = bvh.Closest(q, 0.999 * distance);
    EXPECT_FALSE(short_of.found);
    EXPECT_EQ(short_of.triangle, -1);
    ExpectSameBits(bvh.Closest(q, 1.001 * distance), unbounded);
  }
  // A corner is at distance zero from itself.
  const Eigen::Vector3d corner = sphere.positions.row(7).transpose();
  const SurfacePoint at_corner = bvh.Closest(corner, 0.0);
  EXPECT_TRUE(at_corner.found);
  EXPECT_EQ(at_corner.signed_distance, 0.0);
  EXPECT_EQ(at_corner.point, corner);
}

TEST(TriangleBvhTest, InvalidQueriesFindNothing) {
  const TriangleBvh bvh = BuildOrDie(UnitCube());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(bvh.Closest(Eigen::Vector3d(nan, 0.5, 0.5), kInfinity).found);
  EXPECT_FALSE(bvh.Closest(Eigen::Vector3d(kInfinity, 0.5, 0.5), kInfinity).found);
  EXPECT_FALSE(bvh.Closest(Eigen::Vector3d(0.5, 0.5, 0.5), -1.0).found);
  EXPECT_FALSE(bvh.Closest(Eigen::Vector3d(0.5, 0.5, 0.5), nan).found);
}

// A tree built for other positions must answer exactly like one built for these: the boxes are
// looser but the search is exact, and ties resolve by triangle row, not by tree shape.
TEST(TriangleBvhTest, RefitAnswersLikeAFreshBuild) {
  const TestMesh sphere = Icosphere(3, 1.0);
  TriangleBvh refitted = BuildOrDie(sphere);
  Random random(4, 0);
  TestMesh moved = sphere;
  for (Eigen::Index v = 0; v < moved.positions.rows(); ++v) {
    const Eigen::RowVector3d p = sphere.positions.row(v);
    moved.positions.row(v) = Eigen::RowVector3d(1.3 * p.x() + 0.4, 0.7 * p.y() - 2.0, 2.0 * p.z()) +
                             0.02 * UniformPoint(random, -1.0, 1.0).transpose();
  }
  // The cube has exact ties between triangles at its edges, corners and diagonals.
  const TestMesh cube = UnitCube();
  TestMesh moved_cube = cube;
  moved_cube.positions = (3.0 * cube.positions.array() + 0.25).matrix();
  TriangleBvh refitted_cube = BuildOrDie(cube);

  refitted.Refit(moved.positions);
  refitted_cube.Refit(moved_cube.positions);
  EXPECT_EQ(refitted.positions(), moved.positions);
  const TriangleBvh fresh = BuildOrDie(moved);
  const TriangleBvh fresh_cube = BuildOrDie(moved_cube);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d q = UniformPoint(random, -2.5, 2.5) + Eigen::Vector3d(0.4, -2.0, 0.0);
    for (double max_distance : {kInfinity, 0.1}) {
      ExpectSameBits(refitted.Closest(q, max_distance), fresh.Closest(q, max_distance));
    }
    // Rounded to a 1/8 grid, so that many queries sit exactly on ties.
    const Eigen::Vector3d grid =
        ((UniformPoint(random, -1.0, 4.0) * 8.0).array().round() / 8.0).matrix();
    ExpectSameBits(refitted_cube.Closest(grid, kInfinity), fresh_cube.Closest(grid, kInfinity));
  }
  // And back: the refitted tree answers like the first build again.
  refitted.Refit(sphere.positions);
  const TriangleBvh original = BuildOrDie(sphere);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d q = UniformPoint(random, -1.5, 1.5);
    ExpectSameBits(refitted.Closest(q, kInfinity), original.Closest(q, kInfinity));
  }
}

// A hint only orders the search. The cube's grid queries sit on exact ties between triangles,
// where a hint that won ties it should lose would change the answer.
TEST(TriangleBvhTest, AnyHintGivesTheSameAnswer) {
  const TestMesh sphere = Icosphere(3, 1.0);
  const TriangleBvh bvh = BuildOrDie(sphere);
  const TestMesh cube = UnitCube();
  const TriangleBvh cube_bvh = BuildOrDie(cube);
  const auto sphere_triangles = static_cast<int32_t>(sphere.triangles.rows());
  const auto cube_triangles = static_cast<int32_t>(cube.triangles.rows());
  Random random(5, 0);
  int hint_was_answer = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d q = UniformPoint(random, -1.5, 1.5);
    for (double max_distance : {kInfinity, 0.2}) {
      const SurfacePoint plain = bvh.Closest(q, max_distance);
      // The answer itself, a neighbour's worth of rows away, anywhere, and out of range.
      const int32_t near = plain.found ? plain.triangle : 0;
      for (int32_t hint : {near, (near + 7) % sphere_triangles,
                           static_cast<int32_t>(random.Uniform01() * sphere_triangles), -1,
                           sphere_triangles}) {
        ExpectSameBits(bvh.Closest(q, max_distance, hint), plain);
        if (plain.found && hint == plain.triangle) ++hint_was_answer;
      }
    }
    const Eigen::Vector3d grid =
        ((UniformPoint(random, -0.5, 1.5) * 4.0).array().round() / 4.0).matrix();
    const SurfacePoint plain = cube_bvh.Closest(grid, kInfinity);
    for (int32_t hint = 0; hint < cube_triangles; ++hint) {
      ExpectSameBits(cube_bvh.Closest(grid, kInfinity, hint), plain);
    }
  }
  EXPECT_GT(hint_was_answer, 2000);
}

TEST(TriangleBvhTest, BuildRejectsBadInput) {
  const TestMesh cube = UnitCube();
  EXPECT_THAT(TriangleBvh::Build(cube.positions, Triangles(0, 3)),
              StatusIs(absl::StatusCode::kInvalidArgument, "no triangles"));
  Triangles bad = cube.triangles;
  bad(5, 1) = 8;
  EXPECT_THAT(
      TriangleBvh::Build(cube.positions, bad),
      StatusIs(absl::StatusCode::kInvalidArgument, "triangle 5 corner 1 has vertex index 8"));
  bad(5, 1) = -1;
  EXPECT_THAT(TriangleBvh::Build(cube.positions, bad),
              StatusIs(absl::StatusCode::kInvalidArgument, "vertex index -1"));
  Positions nan_positions = cube.positions;
  nan_positions(3, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT(TriangleBvh::Build(nan_positions, cube.triangles),
              StatusIs(absl::StatusCode::kInvalidArgument, "vertex 3 is not finite"));
  Positions infinite_positions = cube.positions;
  infinite_positions(6, 0) = kInfinity;
  EXPECT_THAT(TriangleBvh::Build(infinite_positions, cube.triangles),
              StatusIs(absl::StatusCode::kInvalidArgument, "vertex 6 is not finite"));
}

// A degenerate triangle (collinear corners) has no face region and no normal of its own;
// queries near it must still get an exact distance, a point on the mesh and a unit normal.
TEST(TriangleBvhTest, DegenerateTrianglesGiveFiniteAnswers) {
  TestMesh mesh;
  mesh.positions.resize(4, 3);
  mesh.positions << 0, 0, 0, 1, 0, 0, 2, 0, 0, 1, 1, 0;
  mesh.triangles.resize(2, 3);
  mesh.triangles << 0, 1, 2, 0, 2, 3;
  const TriangleBvh bvh = BuildOrDie(mesh);
  Random random(5, 0);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d q = UniformPoint(random, -1.0, 3.0);
    const SurfacePoint hit = bvh.Closest(q, kInfinity);
    ExpectConsistent(mesh, q, hit);
    ASSERT_NEAR(std::abs(hit.signed_distance), BruteForceDistance(mesh, q), kTolerance);
  }
}

}  // namespace
}  // namespace fitbase::core
