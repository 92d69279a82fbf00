#include "body/macro_weights.h"

#include <filesystem>
#include <map>
#include <set>

#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::body {
namespace {

using ::testing::DoubleNear;

std::map<std::string, double> AsMap(const std::vector<TargetWeight>& weights) {
  std::map<std::string, double> map;
  for (const TargetWeight& w : weights) {
    EXPECT_TRUE(map.emplace(w.path, w.weight).second) << "duplicate " << w.path;
  }
  return map;
}

TEST(MacroWeightsTest, ThreeLevelsAtTheirCorners) {
  auto at = [](double v) {
    const auto l = ThreeLevels(v, kMuscleLevels);
    return std::array<double, 3>{l[0].weight, l[1].weight, l[2].weight};
  };
  EXPECT_EQ(at(0.0), (std::array<double, 3>{1, 0, 0}));
  EXPECT_EQ(at(0.25), (std::array<double, 3>{0.5, 0.5, 0}));
  EXPECT_EQ(at(0.5), (std::array<double, 3>{0, 1, 0}));
  EXPECT_EQ(at(0.75), (std::array<double, 3>{0, 0.5, 0.5}));
  EXPECT_EQ(at(1.0), (std::array<double, 3>{0, 0, 1}));
  EXPECT_EQ(ThreeLevels(0.3, kWeightLevels)[2].name, "maxweight");
}

TEST(MacroWeightsTest, AgeAndGenderLevels) {
  EXPECT_EQ(AgeLevels(AgeValueFromYears(25))[0].weight, 1.0);
  EXPECT_EQ(AgeLevels(AgeValueFromYears(25))[1].weight, 0.0);
  EXPECT_EQ(AgeLevels(AgeValueFromYears(90))[1].weight, 1.0);
  EXPECT_DOUBLE_EQ(AgeLevels(AgeValueFromYears(57.5))[1].weight, 0.5);
  EXPECT_EQ(GenderLevels(0.0)[0].weight, 1.0);
  EXPECT_EQ(GenderLevels(1.0)[1].weight, 1.0);
  EXPECT_EQ(GenderLevels(0.25)[0].name, "female");
}

TEST(MacroWeightsTest, DefaultHumanWeights) {
  const auto weights = AsMap(ComputeTargetWeights(BodyParams{}));
  // 6 ethnic-gender-young targets at 1/6, 2 (empty) average universal targets at 1/2.
  ASSERT_EQ(weights.size(), 8u);
  EXPECT_THAT(weights.at("macrodetails/asian-male-young.target"), DoubleNear(1.0 / 6, 1e-15));
  EXPECT_THAT(weights.at("macrodetails/universal-female-young-averagemuscle-averageweight.target"),
              DoubleNear(0.5, 1e-15));
}

TEST(MacroWeightsTest, MacroWeightsOfEachFamilySumToOne) {
  BodyParams p;
  p.gender = 0.37;
  p.age_years = 61;
  p.muscle = 0.2;
  p.weight = 0.9;
  p.african = 0.1;
  p.asian = 0.6;
  p.caucasian = 0.3;
  double ethnic = 0, universal = 0;
  for (const TargetWeight& w : ComputeTargetWeights(p)) {
    if (w.path.find("universal-") != std::string::npos) universal += w.weight;
    if (w.path.find("macrodetails/") == 0 && w.path.find('/', 13) == std::string::npos &&
        w.path.find("universal") == std::string::npos) {
      ethnic += w.weight;
    }
  }
  EXPECT_NEAR(ethnic, 1.0, 1e-12);
  EXPECT_NEAR(universal, 1.0, 1e-12);
}

TEST(MacroWeightsTest, LocalModifiersAreOneSided) {
  BodyParams p;
  p.modifiers["measure/measure-bust-circ-decr|incr"] = -0.4;
  p.modifiers["stomach/stomach-navel-down|up"] = 0.7;
  p.modifiers["measure/measure-neck-circ-decr|incr"] = 0.0;
  const auto weights = AsMap(ComputeTargetWeights(p));
  EXPECT_DOUBLE_EQ(weights.at("measure/measure-bust-circ-decr.target"), 0.4);
  EXPECT_EQ(weights.count("measure/measure-bust-circ-incr.target"), 0u);
  EXPECT_DOUBLE_EQ(weights.at("stomach/stomach-navel-up.target"), 0.7);
  EXPECT_EQ(weights.count("measure/measure-neck-circ-decr.target"), 0u);
  EXPECT_EQ(weights.count("measure/measure-neck-circ-incr.target"), 0u);
}

TEST(MacroWeightsTest, MaleBodiesUseNoBreastTargets) {
  BodyParams p;
  p.gender = 1.0;
  p.breast_size = 1.0;
  for (const TargetWeight& w : ComputeTargetWeights(p)) {
    EXPECT_NE(w.path.rfind("breast/", 0), 0u) << w.path;
  }
}

TEST(MacroWeightsTest, AllTargetPathsAreDistinctAndShipped) {
  const std::vector<std::string> paths = AllTargetPaths();
  // 12 ethnic + 36 universal + 72 height + 72 proportions + 144 breast + 2 x 47 local.
  EXPECT_EQ(paths.size(), 430u);
  EXPECT_EQ(std::set<std::string>(paths.begin(), paths.end()).size(), paths.size());
  for (const std::string& path : paths) {
    EXPECT_TRUE(std::filesystem::exists(core::TestDataDir() / "targets" / path)) << path;
  }
}

}  // namespace
}  // namespace fitbase::body
