#include "core/obj_io.h"

#include <fstream>

#include "core/file_util.h"
#include "core/test_support.h"
#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

std::filesystem::path TempPath(const std::string& name) {
  return ProcessTempDir() / name;
}

TEST(ObjIoTest, ReadsBaseMeshInFileOrder) {
  auto mesh = ReadObj(TestDataDir() / "base.obj");
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  EXPECT_EQ(mesh->vertex_count(), 19158);
  EXPECT_EQ(mesh->faces.face_count(), 18486);
  // First and last `v` lines of base.obj.
  EXPECT_NEAR(mesh->positions(0, 1), 7.3299, 1e-6);
  EXPECT_NEAR(mesh->positions(19157, 1), -7.9173, 1e-6);
}

TEST(ObjIoTest, WriteThenReadKeepsVerticesAndCornerOrder) {
  Mesh mesh;
  mesh.topology_id = "test";
  mesh.positions.resize(5, 3);
  mesh.positions << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5, 0.5, 1.25;
  // A quad starting at corner 2 and a triangle: a reader that rotates corners fails.
  mesh.faces.sizes = {4, 3};
  mesh.faces.indices = {2, 3, 0, 1, 2, 1, 4};
  const auto path = TempPath("quad.obj");
  ASSERT_TRUE(WriteObj(path, mesh).ok());
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
  auto read = ReadObj(path);
  ASSERT_TRUE(read.ok()) << read.status();
  EXPECT_EQ(read->positions, mesh.positions);
  EXPECT_EQ(read->faces, mesh.faces);
}

TEST(ObjIoTest, WriteIsDeterministic) {
  Mesh mesh;
  mesh.positions = Positions::Random(20, 3);
  ASSERT_TRUE(WriteObj(TempPath("a.obj"), mesh).ok());
  ASSERT_TRUE(WriteObj(TempPath("b.obj"), mesh).ok());
  EXPECT_EQ(*ReadFileToString(TempPath("a.obj")), *ReadFileToString(TempPath("b.obj")));
}

TEST(ObjIoTest, NonFiniteCoordinateIsAnError) {
  const auto path = TempPath("nan.obj");
  ASSERT_TRUE(WriteFileAtomically(path, "v 0 0 0\nv nan 0 0\nv 0 1 inf\nf 1 2 3\n").ok());
  auto mesh = ReadObj(path);
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.status().code(), absl::StatusCode::kInvalidArgument);
}

TEST(ObjIoTest, MissingOrEmptyFile) {
  EXPECT_EQ(ReadObj(TempPath("missing.obj")).status().code(), absl::StatusCode::kNotFound);
  ASSERT_TRUE(WriteFileAtomically(TempPath("empty.obj"), "# nothing\n").ok());
  EXPECT_EQ(ReadObj(TempPath("empty.obj")).status().code(), absl::StatusCode::kInvalidArgument);
}

// Found by fuzz/body_obj_fuzzer: a face line with no vertex index made Debian's OpenMesh
// fail an assertion and abort the process.
TEST(ObjIoTest, FaceLineWithoutIndicesIsAnErrorNamingTheLine) {
  const auto path = TempPath("bad-face.obj");
  ASSERT_TRUE(
      WriteFileAtomically(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf  of this repository.\n")
          .ok());
  auto mesh = ReadObj(path);
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(mesh.status().message(), ::testing::HasSubstr("line 5"));
}

}  // namespace
}  // namespace fitbase::core
