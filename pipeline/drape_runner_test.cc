#include "pipeline/drape_runner.h"

#include <filesystem>
#include <string>
#include <vector>

#include "body/body_model.h"
#include "body/body_params.h"
#include "core/file_util.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "pipeline/garment_importer.h"
#include "proto/avatar_params_codec.h"
#include "proto/mesh_codec.h"
#include "proto/message_file.h"

namespace fitbase::pipeline {
namespace {

namespace fs = std::filesystem;
using ::fitbase::core::StatusIs;

// A T-shirt and shorts (1,696 vertices) draped, on a short schedule, onto the mean body of its
// two-body basis, scaled about the origin: three different bodies, hence three keys.
class DrapeRunnerTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    absl::StatusOr<body::BodyModel> model = body::BodyModel::Load(core::TestDataDir());
    ASSERT_TRUE(model.ok()) << model.status();
    v1::AvatarBasis basis;
    basis.set_id("drape-runner-test-basis");
    body::BodyParams params;
    params.gender = 0.9;
    *basis.mutable_population()->add_params() = proto::BodyParamsToProto(params);
    params.weight = 0.7;
    *basis.mutable_population()->add_params() = proto::BodyParamsToProto(params);
    const fs::path dir = core::TestDataDir() / "clothes" / "male_casualsuit04";
    GarmentImportRequest request;
    request.obj = {"g.obj", core::ReadFileToString(dir / "male_casualsuit04.obj").value_or("")};
    request.mhclo =
        SourceFile{"g.mhclo", core::ReadFileToString(dir / "male_casualsuit04.mhclo").value_or("")};
    request.sizes = {"M"};
    absl::StatusOr<v1::Garment> garment = ImportGarment(*model, basis, request);
    ASSERT_TRUE(garment.ok()) << garment.status();
    garment_ = new v1::Garment(*std::move(garment));
    absl::StatusOr<core::Mesh> mean = proto::MeshFromProto(garment_->mean_avatar());
    ASSERT_TRUE(mean.ok()) << mean.status();
    mean_body_ = new core::Positions(mean->positions.topRows(body::kBodyVertexCount));
  }
  static void TearDownTestSuite() {
    delete garment_;
    delete mean_body_;
  }

  static std::vector<workers::DrapeTask> Tasks(const std::vector<std::string>& sizes) {
    std::vector<workers::DrapeTask> tasks;
    for (size_t i = 0; i < sizes.size(); ++i) {
      const core::Positions body = *mean_body_ * (1.0 + 0.01 * static_cast<double>(i));
      tasks.push_back(workers::MakeDrapeTask(*garment_, sizes[i], body, {},
                                             {.homotopy_steps = 2, .relax_steps = 1}));
    }
    return tasks;
  }

  static std::vector<const workers::DrapeTask*> Pointers(
      const std::vector<workers::DrapeTask>& tasks) {
    std::vector<const workers::DrapeTask*> pointers;
    for (const workers::DrapeTask& task : tasks) pointers.push_back(&task);
    return pointers;
  }

  static v1::Garment* garment_;
  static core::Positions* mean_body_;
};

v1::Garment* DrapeRunnerTest::garment_ = nullptr;
core::Positions* DrapeRunnerTest::mean_body_ = nullptr;

TEST_F(DrapeRunnerTest, ReturnsTheResultsInTaskOrderAlikeForAnyJobCount) {
  const std::vector<workers::DrapeTask> tasks = Tasks({"M", "M", "M"});
  absl::StatusOr<std::vector<v1::DrapeResult>> one =
      RunDrapeTasks(Pointers(tasks), {.jobs = 1, .label = "one"});
  absl::StatusOr<std::vector<v1::DrapeResult>> three =
      RunDrapeTasks(Pointers(tasks), {.jobs = 3, .label = "three"});
  ASSERT_TRUE(one.ok()) << one.status();
  ASSERT_TRUE(three.ok()) << three.status();
  ASSERT_EQ(one->size(), tasks.size());
  ASSERT_EQ(three->size(), tasks.size());
  // Positions, not whole results: a result's report also says how long its drape took.
  const auto positions = [](const v1::DrapeResult& result) {
    return std::vector<float>(result.positions().begin(), result.positions().end());
  };
  for (size_t i = 0; i < tasks.size(); ++i) {
    EXPECT_EQ((*one)[i].key(), tasks[i].key);
    EXPECT_EQ((*three)[i].key(), tasks[i].key);
    EXPECT_TRUE(positions((*one)[i]) == positions((*three)[i])) << "task " << i;
  }
  EXPECT_FALSE(positions((*one)[0]) == positions((*one)[1]));
}

TEST_F(DrapeRunnerTest, TakesAStoredResultInsteadOfDrapingAgain) {
  const fs::path cache = core::ProcessTempDir() / "cache";
  const std::vector<workers::DrapeTask> tasks = Tasks({"M", "M"});
  absl::StatusOr<std::vector<v1::DrapeResult>> first =
      RunDrapeTasks(Pointers(tasks), {.cache_dir = cache, .jobs = 2});
  ASSERT_TRUE(first.ok()) << first.status();
  for (const workers::DrapeTask& task : tasks) {
    EXPECT_TRUE(fs::exists(cache / (task.key + ".fbd"))) << task.key;
  }
  // A stored result marked by hand: only a run that reads it, not one that drapes, returns it.
  v1::DrapeResult marked = (*first)[1];
  marked.set_positions(0, 123.0f);
  ASSERT_TRUE(proto::WriteMessageFile(cache / (tasks[1].key + ".fbd"), marked).ok());
  absl::StatusOr<std::vector<v1::DrapeResult>> second =
      RunDrapeTasks(Pointers(tasks), {.cache_dir = cache, .jobs = 2});
  ASSERT_TRUE(second.ok()) << second.status();
  EXPECT_EQ((*second)[0].SerializeAsString(), (*first)[0].SerializeAsString()) << "read back";
  EXPECT_EQ((*second)[1].positions(0), 123.0f);
}

TEST_F(DrapeRunnerTest, FailsWithTheKeyOfTheDrapeThatFailed) {
  const std::vector<workers::DrapeTask> tasks = Tasks({"M", "XXL", "M", "M"});
  const fs::path cache = core::ProcessTempDir() / "failing";
  EXPECT_THAT(RunDrapeTasks(Pointers(tasks), {.cache_dir = cache, .jobs = 2}),
              StatusIs(absl::StatusCode::kNotFound, "drape " + tasks[1].key));
  EXPECT_FALSE(fs::exists(cache / (tasks[1].key + ".fbd")));
}

}  // namespace
}  // namespace fitbase::pipeline
