#include "proto/mesh_codec.h"

#include <cmath>
#include <limits>
#include <string>

#include "absl/status/status.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::proto {
namespace {

using ::testing::HasSubstr;

// A quad and a triangle over five vertices, with coordinates float32 cannot hold exactly.
core::Mesh SampleMesh() {
  core::Mesh mesh;
  mesh.topology_id = "test-topology";
  mesh.positions.resize(5, 3);
  mesh.positions << 0.1, -0.2, 0.3,       //
      1.0 / 3.0, 1.7654321, -0.0123456789,  //
      1.23456789, 2.0, 0.5,                 //
      -1.0e-3, 0.0, 1.999999,               //
      0.25, 0.75, -1.5;
  mesh.faces.sizes = {4, 3};
  mesh.faces.indices = {2, 3, 0, 1, 2, 1, 4};
  return mesh;
}

TEST(MeshCodecTest, ToProtoStoresCountsAndFloat32Positions) {
  const core::Mesh mesh = SampleMesh();
  const v1::Mesh message = MeshToProto(mesh);
  EXPECT_EQ(message.topology_id(), "test-topology");
  EXPECT_EQ(message.vertex_count(), 5u);
  ASSERT_EQ(message.positions_size(), 15);
  // xyz interleaved, vertex-major.
  EXPECT_EQ(message.positions(3), static_cast<float>(1.0 / 3.0));
  EXPECT_EQ(message.positions(4), static_cast<float>(1.7654321));
  EXPECT_EQ(message.positions(14), -1.5f);
  EXPECT_THAT(message.face_sizes(), ::testing::ElementsAre(4u, 3u));
  EXPECT_THAT(message.face_indices(), ::testing::ElementsAre(2u, 3u, 0u, 1u, 2u, 1u, 4u));
}

TEST(MeshCodecTest, RoundTripKeepsMeshWithinFloat32Precision) {
  const core::Mesh mesh = SampleMesh();
  auto decoded = MeshFromProto(MeshToProto(mesh));
  ASSERT_TRUE(decoded.ok()) << decoded.status();
  EXPECT_EQ(decoded->topology_id, mesh.topology_id);
  ASSERT_EQ(decoded->vertex_count(), mesh.vertex_count());
  for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
    for (int axis = 0; axis < 3; ++axis) {
      const double expected = mesh.positions(v, axis);
      EXPECT_NEAR(decoded->positions(v, axis), expected, 1e-6 * std::abs(expected))
          << "vertex " << v << " axis " << axis;
    }
  }
  EXPECT_EQ(decoded->faces, mesh.faces);
}

TEST(MeshCodecTest, RoundTripOfFloat32ValuesIsExact) {
  core::Mesh mesh = SampleMesh();
  mesh.positions = mesh.positions.cast<float>().cast<double>();
  auto decoded = MeshFromProto(MeshToProto(mesh));
  ASSERT_TRUE(decoded.ok()) << decoded.status();
  EXPECT_EQ(decoded->positions, mesh.positions);
}

TEST(MeshCodecTest, MeshWithoutFacesIsValid) {
  core::Mesh mesh = SampleMesh();
  mesh.faces = {};
  auto decoded = MeshFromProto(MeshToProto(mesh));
  ASSERT_TRUE(decoded.ok()) << decoded.status();
  EXPECT_EQ(decoded->faces.face_count(), 0);
  EXPECT_EQ(decoded->vertex_count(), 5);
}

void ExpectInvalid(const v1::Mesh& message, const std::string& needle) {
  EXPECT_THAT(MeshFromProto(message), core::StatusIs(absl::StatusCode::kInvalidArgument, needle));
}

TEST(MeshCodecTest, RejectsWrongPositionsCount) {
  v1::Mesh message = MeshToProto(SampleMesh());
  message.mutable_positions()->RemoveLast();
  ExpectInvalid(message, "14 position values for 5 vertices; expected 15");

  message = MeshToProto(SampleMesh());
  message.set_vertex_count(6);
  ExpectInvalid(message, "expected 18");
}

TEST(MeshCodecTest, RejectsNaNPosition) {
  v1::Mesh message = MeshToProto(SampleMesh());
  message.set_positions(7, std::numeric_limits<float>::quiet_NaN());  // Vertex 2, y.
  ExpectInvalid(message, "vertex 2 has a non-finite coordinate");
}

TEST(MeshCodecTest, RejectsInfinitePosition) {
  v1::Mesh message = MeshToProto(SampleMesh());
  message.set_positions(14, -std::numeric_limits<float>::infinity());  // Vertex 4, z.
  ExpectInvalid(message, "vertex 4 has a non-finite coordinate");
}

TEST(MeshCodecTest, RejectsFaceWithFewerThanThreeCorners) {
  v1::Mesh message = MeshToProto(SampleMesh());
  // Sizes 4 + 2 + 1 still add up to the 7 indices: only the size check can catch it.
  message.clear_face_sizes();
  message.add_face_sizes(4);
  message.add_face_sizes(2);
  message.add_face_sizes(1);
  ExpectInvalid(message, "fewer than 3 corners");
}

TEST(MeshCodecTest, RejectsFaceSizesNotSummingToIndices) {
  v1::Mesh message = MeshToProto(SampleMesh());
  message.add_face_indices(0);
  ExpectInvalid(message, "face sizes add up to 7 corners but 8 indices are given");

  message = MeshToProto(SampleMesh());
  message.add_face_sizes(3);
  ExpectInvalid(message, "face sizes add up to 10 corners but 7 indices are given");
}

TEST(MeshCodecTest, RejectsIndexNotBelowVertexCount) {
  v1::Mesh message = MeshToProto(SampleMesh());
  message.set_face_indices(6, 5);  // vertex_count is 5.
  ExpectInvalid(message, "face index 5 is not below vertex_count 5");

  message = MeshToProto(SampleMesh());
  message.set_face_indices(0, 4000000000u);  // Would be negative as int32.
  ExpectInvalid(message, "face index 4000000000");
}

}  // namespace
}  // namespace fitbase::proto
