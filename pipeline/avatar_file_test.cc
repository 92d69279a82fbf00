#include "pipeline/avatar_file.h"


#include <cstdlib>
#include <filesystem>
#include <string>

#include "absl/status/status.h"
#include "body/body_model.h"
#include "core/file_util.h"
#include "core/obj_io.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::pipeline {
namespace {

using ::testing::HasSubstr;


// The default body, built once: loading the model reads every target.
const core::Mesh& DefaultBody() {
  static const core::Mesh* body = [] {
    auto model = body::BodyModel::Load(core::TestDataDir());
    EXPECT_TRUE(model.ok()) << model.status();
    auto mesh = model->BuildBody(body::BodyParams{});
    EXPECT_TRUE(mesh.ok()) << mesh.status();
    return new core::Mesh(std::move(*mesh));
  }();
  return *body;
}

std::filesystem::path WriteAvatar(const std::string& name, const core::Mesh& mesh) {
  const auto path = core::ProcessTempDir() / name;
  const absl::Status status = core::WriteObj(path, mesh);
  EXPECT_TRUE(status.ok()) << status;
  return path;
}

TEST(AvatarFileTest, ReadsBodyAvatarInMeters) {
  const core::Mesh& body = DefaultBody();
  ASSERT_EQ(body.vertex_count(), body::kBodyVertexCount);
  const auto path = WriteAvatar("body.obj", body);
  auto read = ReadAvatarObj(path);
  ASSERT_TRUE(read.ok()) << read.status();
  EXPECT_EQ(read->vertex_count(), 13380);
  EXPECT_EQ(read->topology_id, body::kBodyTopologyId);
  EXPECT_EQ(read->faces, body.faces);
  EXPECT_LE((read->positions - body.positions).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(AvatarFileTest, TruncatedAvatarNamesTheExpectedVertexCount) {
  core::Mesh truncated;
  truncated.positions = DefaultBody().positions.topRows(100);
  const auto path = WriteAvatar("truncated.obj", truncated);
  auto read = ReadAvatarObj(path);
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.status().code(), absl::StatusCode::kInvalidArgument);
  const std::string message(read.status().message());
  EXPECT_THAT(message, HasSubstr("truncated.obj"));
  EXPECT_THAT(message, HasSubstr("has 100 vertices"));
  EXPECT_THAT(message, HasSubstr("13380"));
}

TEST(AvatarFileTest, DecimeterAvatarIsRejectedAsNotMeters) {
  core::Mesh decimeters = DefaultBody();
  decimeters.positions *= 10.0;
  const auto path = WriteAvatar("decimeters.obj", decimeters);
  auto read = ReadAvatarObj(path);
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.status().code(), absl::StatusCode::kInvalidArgument);
  const std::string message(read.status().message());
  EXPECT_THAT(message, HasSubstr("decimeters.obj"));
  EXPECT_THAT(message, HasSubstr("meters"));
}

TEST(AvatarFileTest, MillimeterScaleIsRejectedToo) {
  core::Mesh tiny = DefaultBody();
  tiny.positions *= 0.1;  // A body 17 cm tall.
  auto read = ReadAvatarObj(WriteAvatar("tiny.obj", tiny));
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(read.status().message()), HasSubstr("meters"));
}

TEST(AvatarFileTest, NanCoordinateIsAnError) {
  // The valid body with one coordinate replaced by "nan": whatever OpenMesh makes of it, the
  // result must be an error, not a crash or a silently wrong avatar.
  const auto valid = WriteAvatar("valid_for_nan.obj", DefaultBody());
  auto text = core::ReadFileToString(valid);
  ASSERT_TRUE(text.ok()) << text.status();
  const size_t first_vertex = text->find("\nv ");
  ASSERT_NE(first_vertex, std::string::npos);
  const size_t line_end = text->find('\n', first_vertex + 1);
  text->replace(first_vertex + 1, line_end - first_vertex - 1, "v 0.1 nan 0.2");
  const auto path = core::ProcessTempDir() / "nan.obj";
  ASSERT_TRUE(core::WriteFileAtomically(path, *text).ok());
  auto read = ReadAvatarObj(path);
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.status().code(), absl::StatusCode::kInvalidArgument) << read.status();
  EXPECT_THAT(std::string(read.status().message()), HasSubstr("nan.obj"));
  EXPECT_THAT(std::string(read.status().message()), HasSubstr("finite"));
}

TEST(AvatarFileTest, MissingFileIsNotFound) {
  auto read = ReadAvatarObj(core::ProcessTempDir() / "absent.obj");
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(read.status().message()), HasSubstr("absent.obj"));
}

}  // namespace
}  // namespace fitbase::pipeline
