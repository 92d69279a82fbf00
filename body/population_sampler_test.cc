#include "body/population_sampler.h"

#include <cmath>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "gtest/gtest.h"

namespace fitbase::body {
namespace {

constexpr int kSamples = 2000;
constexpr uint64_t kSeed = 20240601;
constexpr PopulationPreset kPresets[] = {PopulationPreset::kWomen, PopulationPreset::kMen,
                                         PopulationPreset::kAll};

struct Moments {
  double mean;
  double sd;
};

double NormalPdf(double x) { return std::exp(-0.5 * x * x) / std::sqrt(2.0 * std::numbers::pi); }
double NormalCdf(double x) { return 0.5 * std::erfc(-x / std::numbers::sqrt2); }

// Exact mean and sd of Normal(mean, sd) conditioned on [lo, hi].
Moments TruncatedNormalMoments(double mean, double sd, double lo, double hi) {
  const double a = (lo - mean) / sd;
  const double b = (hi - mean) / sd;
  const double z = NormalCdf(b) - NormalCdf(a);
  const double shift = (NormalPdf(a) - NormalPdf(b)) / z;
  const double variance = 1.0 + (a * NormalPdf(a) - b * NormalPdf(b)) / z - shift * shift;
  return {mean + sd * shift, sd * std::sqrt(variance)};
}

std::vector<BodyParams> SamplePopulation(PopulationPreset preset) {
  std::vector<BodyParams> population;
  for (int i = 0; i < kSamples; ++i) population.push_back(SampleBodyParams(preset, kSeed, i));
  return population;
}

std::vector<double> Values(const std::vector<BodyParams>& population, double BodyParams::*field) {
  std::vector<double> values;
  for (const BodyParams& params : population) values.push_back(params.*field);
  return values;
}

std::vector<double> ModifierValues(const std::vector<BodyParams>& population,
                                   const std::string& name) {
  std::vector<double> values;
  for (const BodyParams& params : population) values.push_back(params.modifiers.at(name));
  return values;
}

// The mean must lie within five standard errors and the sd within 10% (about six standard
// errors at 2000 samples); the draws are seeded, so a pass is stable.
void ExpectMoments(const std::vector<double>& values, Moments expected, const std::string& what) {
  double sum = 0.0;
  double sum_sq = 0.0;
  for (double x : values) {
    sum += x;
    sum_sq += x * x;
  }
  const double n = static_cast<double>(values.size());
  const double mean = sum / n;
  const double sd = std::sqrt(sum_sq / n - mean * mean);
  EXPECT_NEAR(mean, expected.mean, 5.0 * expected.sd / std::sqrt(n)) << what;
  EXPECT_NEAR(sd, expected.sd, 0.1 * expected.sd) << what;
}

TEST(PopulationSamplerTest, SameInputsGiveBitwiseEqualParams) {
  for (PopulationPreset preset : kPresets) {
    for (uint64_t index = 0; index < 50; ++index) {
      EXPECT_EQ(SampleBodyParams(preset, kSeed, index), SampleBodyParams(preset, kSeed, index));
    }
  }
}

TEST(PopulationSamplerTest, DifferentSeedsAndIndicesDiffer) {
  for (PopulationPreset preset : kPresets) {
    for (uint64_t index = 0; index < 50; ++index) {
      const BodyParams params = SampleBodyParams(preset, kSeed, index);
      EXPECT_NE(params, SampleBodyParams(preset, kSeed + 1, index));
      EXPECT_NE(params, SampleBodyParams(preset, kSeed, index + 1));
    }
  }
}

TEST(PopulationSamplerTest, SmallPopulationIsPrefixOfLargerOne) {
  std::vector<BodyParams> small;
  for (uint64_t index = 0; index < 10; ++index) {
    small.push_back(SampleBodyParams(PopulationPreset::kAll, kSeed, index));
  }
  // Drawn backwards to show that no avatar depends on those sampled before it.
  std::vector<BodyParams> large(30);
  for (uint64_t index = large.size(); index-- > 0;) {
    large[index] = SampleBodyParams(PopulationPreset::kAll, kSeed, index);
  }
  for (size_t index = 0; index < small.size(); ++index) EXPECT_EQ(large[index], small[index]);
}

TEST(PopulationSamplerTest, EverySampleIsValid) {
  for (PopulationPreset preset : kPresets) {
    for (const BodyParams& params : SamplePopulation(preset)) {
      ASSERT_TRUE(ValidateBodyParams(params).ok())
          << PopulationPresetName(preset) << ": " << ValidateBodyParams(params);
      ASSERT_GE(params.age_years, 25.0);
      ASSERT_LE(params.age_years, 70.0);
    }
  }
}

TEST(PopulationSamplerTest, EveryAvatarHasTheSameShapeModifierKeys) {
  std::set<std::string> expected_keys;
  for (const auto& [name, value] : SampleBodyParams(PopulationPreset::kWomen, kSeed, 0).modifiers) {
    expected_keys.insert(name);
    EXPECT_EQ(name.find("-trans-"), std::string::npos) << name;
    EXPECT_EQ(name.find("nipple"), std::string::npos) << name;
    EXPECT_EQ(name.find("navel"), std::string::npos) << name;
  }
  EXPECT_TRUE(expected_keys.contains("measure/measure-waist-circ-decr|incr"));
  EXPECT_TRUE(expected_keys.contains("breast/breast-volume-vert-down|up"));
  for (PopulationPreset preset : kPresets) {
    for (const BodyParams& params : SamplePopulation(preset)) {
      std::set<std::string> keys;
      for (const auto& [name, value] : params.modifiers) keys.insert(name);
      ASSERT_EQ(keys, expected_keys) << PopulationPresetName(preset);
    }
  }
}

TEST(PopulationSamplerTest, WomenAreFemaleAndMenAreMale) {
  for (const BodyParams& params : SamplePopulation(PopulationPreset::kWomen)) {
    ASSERT_LT(params.gender, 0.5);
  }
  for (const BodyParams& params : SamplePopulation(PopulationPreset::kMen)) {
    ASSERT_GT(params.gender, 0.5);
    // Men keep MakeHuman's neutral breast parameters and no breast shape modifiers.
    ASSERT_EQ(params.breast_size, 0.5);
    ASSERT_EQ(params.breast_firmness, 0.5);
    ASSERT_EQ(params.modifiers.at("breast/breast-dist-decr|incr"), 0.0);
    ASSERT_EQ(params.modifiers.at("breast/breast-point-decr|incr"), 0.0);
    ASSERT_EQ(params.modifiers.at("breast/breast-volume-vert-down|up"), 0.0);
  }
}

TEST(PopulationSamplerTest, AllMixesBothClustersEvenly) {
  int women = 0;
  for (const BodyParams& params : SamplePopulation(PopulationPreset::kAll)) {
    // No avatar falls between the two clusters.
    ASSERT_TRUE(params.gender <= 0.25 || params.gender >= 0.75) << params.gender;
    if (params.gender < 0.5) ++women;
  }
  EXPECT_GE(women, 0.4 * kSamples);
  EXPECT_LE(women, 0.6 * kSamples);
}

TEST(PopulationSamplerTest, WomenFollowDocumentedDistributions) {
  const std::vector<BodyParams> women = SamplePopulation(PopulationPreset::kWomen);
  ExpectMoments(Values(women, &BodyParams::gender), TruncatedNormalMoments(0.05, 0.05, 0.0, 0.25),
                "gender");
  ExpectMoments(Values(women, &BodyParams::age_years), {47.5, 45.0 / std::sqrt(12.0)}, "age_years");
  ExpectMoments(Values(women, &BodyParams::muscle), TruncatedNormalMoments(0.5, 0.12, 0.2, 0.85),
                "muscle");
  ExpectMoments(Values(women, &BodyParams::weight), TruncatedNormalMoments(0.5, 0.15, 0.15, 0.9),
                "weight");
  ExpectMoments(Values(women, &BodyParams::height), TruncatedNormalMoments(0.5, 0.15, 0.15, 0.85),
                "height");
  ExpectMoments(Values(women, &BodyParams::proportions),
                TruncatedNormalMoments(0.5, 0.15, 0.2, 0.8), "proportions");
  ExpectMoments(Values(women, &BodyParams::breast_size),
                TruncatedNormalMoments(0.5, 0.15, 0.1, 0.9), "breast_size");
  ExpectMoments(Values(women, &BodyParams::breast_firmness),
                TruncatedNormalMoments(0.5, 0.15, 0.1, 0.9), "breast_firmness");
  // Each share of a flat Dirichlet over 3 is Beta(1, 2).
  const Moments share = {1.0 / 3.0, std::sqrt(2.0 / 36.0)};
  ExpectMoments(Values(women, &BodyParams::african), share, "african");
  ExpectMoments(Values(women, &BodyParams::asian), share, "asian");
  ExpectMoments(Values(women, &BodyParams::caucasian), share, "caucasian");
  for (const std::string name :
       {"measure/measure-waist-circ-decr|incr", "hip/hip-scale-horiz-decr|incr",
        "breast/breast-point-decr|incr"}) {
    ExpectMoments(ModifierValues(women, name), TruncatedNormalMoments(0.0, 0.2, -0.6, 0.6), name);
  }
  ExpectMoments(ModifierValues(women, "stomach/stomach-pregnant-decr|incr"),
                TruncatedNormalMoments(0.0, 0.1, -0.3, 0.3), "stomach pregnant");
}

TEST(PopulationSamplerTest, MenFollowDocumentedDistributions) {
  const std::vector<BodyParams> men = SamplePopulation(PopulationPreset::kMen);
  ExpectMoments(Values(men, &BodyParams::gender), TruncatedNormalMoments(0.95, 0.05, 0.75, 1.0),
                "gender");
  ExpectMoments(Values(men, &BodyParams::weight), TruncatedNormalMoments(0.5, 0.15, 0.15, 0.9),
                "weight");
  ExpectMoments(ModifierValues(men, "measure/measure-waist-circ-decr|incr"),
                TruncatedNormalMoments(0.0, 0.2, -0.6, 0.6), "waist circumference");
}

TEST(PopulationSamplerTest, PresetNamesRoundTrip) {
  for (PopulationPreset preset : kPresets) {
    const absl::StatusOr<PopulationPreset> parsed =
        ParsePopulationPreset(PopulationPresetName(preset));
    ASSERT_TRUE(parsed.ok()) << parsed.status();
    EXPECT_EQ(*parsed, preset);
  }
  EXPECT_EQ(PopulationPresetName(PopulationPreset::kWomen), "women");
  EXPECT_EQ(PopulationPresetName(PopulationPreset::kMen), "men");
  EXPECT_EQ(PopulationPresetName(PopulationPreset::kAll), "all");
}

TEST(PopulationSamplerTest, UnknownPresetIsRejectedWithValidNames) {
  const absl::StatusOr<PopulationPreset> parsed = ParsePopulationPreset("kids");
  ASSERT_EQ(parsed.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(parsed.status().message().find("women, men, all"), std::string::npos)
      << parsed.status();
}

}  // namespace
}  // namespace fitbase::body
