#include "pipeline/population_folder.h"


#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "body/body_model.h"
#include "body/population_sampler.h"
#include "core/file_util.h"
#include "core/obj_io.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "proto/avatar_params_codec.h"

namespace fitbase::pipeline {
namespace {

using ::testing::HasSubstr;

constexpr body::PopulationPreset kPreset = body::PopulationPreset::kWomen;
constexpr uint64_t kSeed = 7;
constexpr int64_t kCount = 3;

namespace fs = std::filesystem;


const body::BodyModel& Model() {
  static const body::BodyModel* model = [] {
    auto loaded = body::BodyModel::Load(core::TestDataDir());
    EXPECT_TRUE(loaded.ok()) << loaded.status();
    return new body::BodyModel(std::move(*loaded));
  }();
  return *model;
}

// The folder for (women, 7, 3), written once and shared; tests that break it work on copies.
const fs::path& WrittenFolder() {
  static const fs::path* dir = [] {
    auto* path = new fs::path(core::ProcessTempDir() / "women-7-3");
    const absl::Status status = WritePopulationFolder(Model(), kPreset, kSeed, kCount, *path);
    EXPECT_TRUE(status.ok()) << status;
    return path;
  }();
  return *dir;
}

fs::path CopyOfWrittenFolder(const std::string& name) {
  const fs::path copy = core::ProcessTempDir() / name;
  fs::remove_all(copy);
  fs::copy(WrittenFolder(), copy, fs::copy_options::recursive);
  return copy;
}

std::string ReadFile(const fs::path& path) {
  auto bytes = core::ReadFileToString(path);
  EXPECT_TRUE(bytes.ok()) << bytes.status();
  return bytes.ok() ? *bytes : std::string();
}

TEST(PopulationFolderTest, WritesTheDocumentedFiles) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(WrittenFolder())) {
    names.push_back(entry.path().filename().string());
  }
  EXPECT_THAT(names, ::testing::UnorderedElementsAre("population.json", "params.jsonl",
                                                      "avatar-00000.obj", "avatar-00001.obj",
                                                      "avatar-00002.obj"));
  const std::vector<std::string> lines =
      absl::StrSplit(ReadFile(WrittenFolder() / "params.jsonl"), '\n', absl::SkipEmpty());
  EXPECT_EQ(lines.size(), 3u);
}

TEST(PopulationFolderTest, ReadBackGivesProvenanceParamsAndBodies) {
  auto population = ReadPopulationFolder(WrittenFolder());
  ASSERT_TRUE(population.ok()) << population.status();
  EXPECT_EQ(population->provenance.preset(), "women");
  EXPECT_EQ(population->provenance.seed(), kSeed);
  EXPECT_EQ(population->provenance.count(), 3u);
  ASSERT_EQ(population->provenance.params_size(), 3);
  ASSERT_EQ(population->avatar_files.size(), 3u);
  EXPECT_EQ(population->avatar_files[2].filename(), "avatar-00002.obj");
  ASSERT_EQ(population->samples.rows(), 3 * body::kBodyVertexCount);
  ASSERT_EQ(population->samples.rows(), 40140);
  ASSERT_EQ(population->samples.cols(), 3);
  EXPECT_EQ(population->faces, Model().body_faces());

  auto sampler = body::PopulationSampler::Create(Model());
  ASSERT_TRUE(sampler.ok()) << sampler.status();
  for (int i = 0; i < 3; ++i) {
    auto sampled = sampler->Sample(kPreset, kSeed, i);
    ASSERT_TRUE(sampled.ok()) << sampled.status();
    const body::BodyParams expected = *sampled;
    auto params = proto::BodyParamsFromProto(population->provenance.params(i));
    ASSERT_TRUE(params.ok()) << params.status();
    EXPECT_EQ(*params, expected) << "avatar " << i;

    auto body = Model().BuildBody(expected);
    ASSERT_TRUE(body.ok()) << body.status();
    const Eigen::Map<const Eigen::VectorXd> flat(body->positions.data(), body->positions.size());
    EXPECT_LE((population->samples.col(i) - flat).cwiseAbs().maxCoeff(), 1e-6) << "avatar " << i;
  }
  // The avatars differ: a reader that repeated one file would fail here.
  EXPECT_GT((population->samples.col(0) - population->samples.col(1)).cwiseAbs().maxCoeff(),
            1e-3);
}

TEST(PopulationFolderTest, WritingTwiceGivesIdenticalBytes) {
  const fs::path again = core::ProcessTempDir() / "women-7-3-again";
  fs::remove_all(again);
  const absl::Status status = WritePopulationFolder(Model(), kPreset, kSeed, kCount, again);
  ASSERT_TRUE(status.ok()) << status;
  for (const std::string name : {"params.jsonl", "population.json", "avatar-00000.obj",
                                 "avatar-00001.obj", "avatar-00002.obj"}) {
    const std::string first = ReadFile(WrittenFolder() / name);
    EXPECT_FALSE(first.empty()) << name;
    EXPECT_TRUE(first == ReadFile(again / name)) << name << " differs";
  }
  EXPECT_FALSE(fs::exists(again / "params.jsonl.tmp"));
}

TEST(PopulationFolderTest, CorruptedParamsLineIsNamed) {
  const fs::path dir = CopyOfWrittenFolder("corrupt-params");
  std::vector<std::string> lines =
      absl::StrSplit(ReadFile(dir / "params.jsonl"), '\n', absl::SkipEmpty());
  ASSERT_EQ(lines.size(), 3u);
  lines[1] = lines[1].substr(0, lines[1].size() / 2);  // Cut mid-object.
  ASSERT_TRUE(
      core::WriteFileAtomically(dir / "params.jsonl", absl::StrJoin(lines, "\n") + "\n").ok());
  auto population = ReadPopulationFolder(dir);
  ASSERT_FALSE(population.ok());
  EXPECT_EQ(population.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(population.status().message()), HasSubstr("params.jsonl line 2"));
}

TEST(PopulationFolderTest, OutOfRangeParamsLineIsNamed) {
  const fs::path dir = CopyOfWrittenFolder("bad-age");
  std::vector<std::string> lines =
      absl::StrSplit(ReadFile(dir / "params.jsonl"), '\n', absl::SkipEmpty());
  ASSERT_EQ(lines.size(), 3u);
  lines[2] = R"({"age_years": 12})";
  ASSERT_TRUE(
      core::WriteFileAtomically(dir / "params.jsonl", absl::StrJoin(lines, "\n") + "\n").ok());
  auto population = ReadPopulationFolder(dir);
  ASSERT_FALSE(population.ok());
  EXPECT_EQ(population.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(population.status().message()), HasSubstr("line 3"));
  EXPECT_THAT(std::string(population.status().message()), HasSubstr("age_years"));
}

TEST(PopulationFolderTest, ParamsLineCountMustMatchCount) {
  const fs::path dir = CopyOfWrittenFolder("missing-line");
  std::vector<std::string> lines =
      absl::StrSplit(ReadFile(dir / "params.jsonl"), '\n', absl::SkipEmpty());
  lines.pop_back();
  ASSERT_TRUE(
      core::WriteFileAtomically(dir / "params.jsonl", absl::StrJoin(lines, "\n") + "\n").ok());
  auto population = ReadPopulationFolder(dir);
  ASSERT_FALSE(population.ok());
  EXPECT_EQ(population.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(population.status().message()), HasSubstr("has 2 lines"));
}

TEST(PopulationFolderTest, AvatarWithWrongVertexCountIsNamed) {
  const fs::path dir = CopyOfWrittenFolder("short-avatar");
  core::Mesh truncated;
  truncated.positions = Model().BuildBody(body::BodyParams{})->positions.topRows(500);
  ASSERT_TRUE(core::WriteObj(dir / "avatar-00001.obj", truncated).ok());
  auto population = ReadPopulationFolder(dir);
  ASSERT_FALSE(population.ok());
  EXPECT_EQ(population.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(population.status().message()), HasSubstr("avatar-00001.obj"));
  EXPECT_THAT(std::string(population.status().message()), HasSubstr("500 vertices"));
}

TEST(PopulationFolderTest, MissingAvatarFileIsAnError) {
  const fs::path dir = CopyOfWrittenFolder("missing-avatar");
  fs::remove(dir / "avatar-00002.obj");
  auto population = ReadPopulationFolder(dir);
  ASSERT_FALSE(population.ok());
  EXPECT_EQ(population.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(population.status().message()), HasSubstr("avatar-00002.obj"));
}

TEST(PopulationFolderTest, FolderOfObjsWithoutProvenanceIsReadInNameOrder) {
  const fs::path dir = core::ProcessTempDir() / "plain-objs";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // Copied under names whose order differs from the avatar indices.
  fs::copy_file(WrittenFolder() / "avatar-00002.obj", dir / "a.obj");
  fs::copy_file(WrittenFolder() / "avatar-00000.obj", dir / "b.obj");
  ASSERT_TRUE(core::WriteFileAtomically(dir / "notes.txt", "not an avatar").ok());
  auto population = ReadPopulationFolder(dir);
  ASSERT_TRUE(population.ok()) << population.status();
  EXPECT_EQ(population->provenance.preset(), "");
  EXPECT_EQ(population->provenance.params_size(), 0);
  EXPECT_EQ(population->provenance.count(), 2u);
  ASSERT_EQ(population->samples.cols(), 2);

  auto written = ReadPopulationFolder(WrittenFolder());
  ASSERT_TRUE(written.ok()) << written.status();
  EXPECT_EQ(population->samples.col(0), written->samples.col(2));
  EXPECT_EQ(population->samples.col(1), written->samples.col(0));
}

TEST(PopulationFolderTest, FewerThanTwoAvatarsIsAnError) {
  const fs::path single = core::ProcessTempDir() / "single";
  fs::remove_all(single);
  ASSERT_TRUE(WritePopulationFolder(Model(), kPreset, kSeed, 1, single).ok());
  auto population = ReadPopulationFolder(single);
  ASSERT_FALSE(population.ok());
  EXPECT_EQ(population.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(population.status().message()), HasSubstr("at least 2"));

  const fs::path empty = core::ProcessTempDir() / "empty";
  fs::create_directories(empty);
  population = ReadPopulationFolder(empty);
  ASSERT_FALSE(population.ok());
  EXPECT_EQ(population.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(population.status().message()), HasSubstr("holds 0 avatars"));
}

TEST(PopulationFolderTest, MissingFolderIsNotFound) {
  auto population = ReadPopulationFolder(core::ProcessTempDir() / "absent");
  EXPECT_EQ(population.status().code(), absl::StatusCode::kNotFound);
}

}  // namespace
}  // namespace fitbase::pipeline
