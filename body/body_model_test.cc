#include "body/body_model.h"

#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "core/test_support.h"
#include "gtest/gtest.h"

namespace fitbase::body {
namespace {

// The expected bodies are computed here without any of fitbase's parsing or weighting code:
// base.obj and the target files are read with plain streams, and the weights are written out
// by hand from the rules in data/makehuman/README.md.
using Expected = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

Expected ReadBaseByHand() {
  std::ifstream in(core::TestDataDir() / "base.obj");
  Expected base(kFullVertexCount, 3);
  std::string line;
  int v = 0;
  while (std::getline(in, line)) {
    if (line.rfind("v ", 0) != 0) continue;
    std::istringstream fields(line.substr(2));
    fields >> base(v, 0) >> base(v, 1) >> base(v, 2);
    ++v;
  }
  EXPECT_EQ(v, kFullVertexCount);
  return base;
}

void AddTargetByHand(const std::string& path, double weight, Expected& positions) {
  std::ifstream in(core::TestDataDir() / "targets" / path);
  ASSERT_TRUE(in) << path;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    int index;
    double dx, dy, dz;
    fields >> index >> dx >> dy >> dz;
    positions.row(index) += weight * Eigen::RowVector3d(dx, dy, dz);
  }
}

class BodyModelTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    auto model = BodyModel::Load(core::TestDataDir());
    ASSERT_TRUE(model.ok()) << model.status();
    model_ = new BodyModel(*std::move(model));
    base_ = new Expected(ReadBaseByHand());
  }
  static void TearDownTestSuite() {
    delete model_;
    delete base_;
  }

  // Builds the full mesh for `params` and checks it against base + sum(weight * target), in
  // meters, to 1e-6 m on every vertex.
  void ExpectMatches(const BodyParams& params, const std::map<std::string, double>& weights) {
    Expected expected = *base_;
    for (const auto& [path, weight] : weights) AddTargetByHand(path, weight, expected);
    expected *= 0.1;
    auto mesh = model_->BuildFullMesh(params);
    ASSERT_TRUE(mesh.ok()) << mesh.status();
    ASSERT_EQ(mesh->vertex_count(), kFullVertexCount);
    EXPECT_LT((mesh->positions - expected).cwiseAbs().maxCoeff(), 1e-6);
    auto body = model_->BuildBody(params);
    ASSERT_TRUE(body.ok());
    EXPECT_EQ(body->positions, mesh->positions.topRows(kBodyVertexCount));
  }

  static BodyModel* model_;
  static Expected* base_;
};

BodyModel* BodyModelTest::model_ = nullptr;
Expected* BodyModelTest::base_ = nullptr;

TEST_F(BodyModelTest, DefaultParametersGiveMakeHumansDefaultHuman) {
  // Age 25 is "young" only; gender 0.5 splits female/male; every ethnic share is 1/3; the
  // average muscle/weight universal targets are empty, height and proportions are neutral,
  // and an average cup of average firmness is the base breast.
  std::map<std::string, double> weights;
  for (const char* ethnic : {"african", "asian", "caucasian"}) {
    for (const char* gender : {"female", "male"}) {
      weights[std::string("macrodetails/") + ethnic + "-" + gender + "-young.target"] = 1.0 / 6;
    }
  }
  ExpectMatches(BodyParams{}, weights);
}

TEST_F(BodyModelTest, CornerParametersSelectSingleTargets) {
  BodyParams p;
  p.gender = 0;
  p.age_years = 90;
  p.muscle = 1;
  p.weight = 0;
  p.height = 1;
  p.proportions = 0;
  p.african = 1;
  p.asian = 0;
  p.caucasian = 0;
  p.breast_size = 1;
  p.breast_firmness = 0;
  p.modifiers["measure/measure-waist-circ-decr|incr"] = 0.5;
  p.modifiers["hip/hip-scale-horiz-decr|incr"] = -1;
  ExpectMatches(p, {
      {"macrodetails/african-female-old.target", 1},
      {"macrodetails/universal-female-old-maxmuscle-minweight.target", 1},
      {"macrodetails/height/female-old-maxmuscle-minweight-maxheight.target", 1},
      {"macrodetails/proportions/female-old-maxmuscle-minweight-uncommonproportions.target", 1},
      {"breast/female-old-maxmuscle-minweight-maxcup-minfirmness.target", 1},
      {"measure/measure-waist-circ-incr.target", 0.5},
      {"hip/hip-scale-horiz-decr.target", 1},
  });
}

TEST_F(BodyModelTest, MixedParametersBlendEveryLevel) {
  BodyParams p;
  p.gender = 0.3;        // female 0.7, male 0.3
  p.age_years = 57.5;    // a = 0.75: young 0.5, old 0.5
  p.muscle = 0.75;       // average 0.5, max 0.5
  p.weight = 0.25;       // min 0.5, average 0.5
  p.height = 0.25;       // minheight 0.5
  p.proportions = 0.8;   // idealproportions 0.6
  p.african = 0.2;
  p.asian = 0.3;
  p.caucasian = 0.5;
  p.breast_size = 0.75;  // averagecup 0.5, maxcup 0.5
  p.breast_firmness = 0.5;
  p.modifiers["torso/torso-scale-depth-decr|incr"] = -0.25;
  std::map<std::string, double> weights;
  const std::pair<const char*, double> genders[] = {{"female", 0.7}, {"male", 0.3}};
  const std::pair<const char*, double> ages[] = {{"young", 0.5}, {"old", 0.5}};
  const std::pair<const char*, double> ethnics[] = {{"african", 0.2}, {"asian", 0.3},
                                                    {"caucasian", 0.5}};
  const std::pair<const char*, double> muscles[] = {{"averagemuscle", 0.5}, {"maxmuscle", 0.5}};
  const std::pair<const char*, double> masses[] = {{"minweight", 0.5}, {"averageweight", 0.5}};
  for (auto [g, wg] : genders) {
    for (auto [a, wa] : ages) {
      for (auto [e, we] : ethnics) {
        weights[std::string("macrodetails/") + e + "-" + g + "-" + a + ".target"] = we * wg * wa;
      }
      for (auto [m, wm] : muscles) {
        for (auto [w, ww] : masses) {
          const std::string body = std::string(g) + "-" + a + "-" + m + "-" + w;
          const double base = wg * wa * wm * ww;
          weights["macrodetails/universal-" + body + ".target"] = base;
          weights["macrodetails/height/" + body + "-minheight.target"] = base * 0.5;
          weights["macrodetails/proportions/" + body + "-idealproportions.target"] = base * 0.6;
          if (std::string(g) == "female") {
            weights["breast/" + body + "-maxcup-averagefirmness.target"] = base * 0.5;
          }
        }
      }
    }
  }
  weights["torso/torso-scale-depth-decr.target"] = 0.25;
  ExpectMatches(p, weights);
}

TEST_F(BodyModelTest, BodyIsTheSkinGroupInMeters) {
  auto body = model_->BuildBody(BodyParams{});
  ASSERT_TRUE(body.ok());
  EXPECT_EQ(body->topology_id, kBodyTopologyId);
  EXPECT_EQ(body->vertex_count(), kBodyVertexCount);
  EXPECT_EQ(body->faces.face_count(), 13378);
  const double height = body->positions.col(1).maxCoeff() - body->positions.col(1).minCoeff();
  EXPECT_GT(height, 1.5);
  EXPECT_LT(height, 1.9);
}

TEST_F(BodyModelTest, InvalidParametersAreRejected) {
  BodyParams p;
  p.weight = std::nan("");
  auto mesh = model_->BuildBody(p);
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(mesh.status().message().find("weight"), absl::string_view::npos);
}

TEST(BodyModelLoadTest, MissingTargetNamesTheFile) {
  const auto dir = core::ProcessTempDir() / "partial_makehuman";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "targets");
  std::filesystem::copy_file(core::TestDataDir() / "base.obj", dir / "base.obj");
  auto model = BodyModel::Load(dir);
  ASSERT_FALSE(model.ok());
  EXPECT_EQ(model.status().code(), absl::StatusCode::kNotFound);
  EXPECT_NE(model.status().message().find(".target"), absl::string_view::npos);
}

}  // namespace
}  // namespace fitbase::body
