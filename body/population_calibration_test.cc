#include "body/population_calibration.h"

#include <cmath>

#include "Eigen/Cholesky"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::body {
namespace {

class PopulationSamplerTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    auto model = BodyModel::Load(core::TestDataDir());
    ASSERT_TRUE(model.ok()) << model.status();
    model_ = new BodyModel(*std::move(model));
    auto sampler = PopulationSampler::Create(*model_);
    ASSERT_TRUE(sampler.ok()) << sampler.status();
    sampler_ = new PopulationSampler(*std::move(sampler));
  }
  static BodyModel* model_;
  static PopulationSampler* sampler_;
};
BodyModel* PopulationSamplerTest::model_ = nullptr;
PopulationSampler* PopulationSamplerTest::sampler_ = nullptr;

TEST_F(PopulationSamplerTest, CalibratedAvatarsMeasureWhatWasDrawnForThem) {
  // Within ISO 20685-1's allowances: 4 mm stature, 9 mm large girths; weight within 0.5 kg.
  const std::array<double, kSurveyMeasurementCount> allowance = {0.004, 0.5, 0.009, 0.009, 0.009};
  int hits = 0;
  constexpr int kAvatars = 12;
  for (PopulationPreset preset : {PopulationPreset::kWomen, PopulationPreset::kMen}) {
    for (int i = 0; i < kAvatars / 2; ++i) {
      auto avatar = sampler_->SampleCalibrated(preset, 7, i);
      ASSERT_TRUE(avatar.ok()) << avatar.status();
      bool hit = true;
      for (int k = 0; k < kSurveyMeasurementCount; ++k) {
        hit = hit && std::abs(avatar->measured[k] - avatar->target[k]) <= allowance[k];
      }
      hits += hit;
      // The body built from the returned parameters is the one measured.
      auto body = model_->BuildBody(avatar->params);
      ASSERT_TRUE(body.ok());
      auto measured = MeasureBody(*body);
      ASSERT_TRUE(measured.ok());
      EXPECT_NEAR((*measured)[static_cast<int>(Measurement::kStature)], avatar->measured[0], 1e-9);
    }
  }
  EXPECT_GE(hits, kAvatars - 1);
}

TEST_F(PopulationSamplerTest, SamplesAreDeterministicAndPrefixFree) {
  auto a = sampler_->Sample(PopulationPreset::kAll, 3, 5);
  auto b = sampler_->Sample(PopulationPreset::kAll, 3, 5);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(*a, *b);
  auto other = sampler_->Sample(PopulationPreset::kAll, 4, 5);
  ASSERT_TRUE(other.ok());
  EXPECT_NE(*a, *other);
}

TEST_F(PopulationSamplerTest, WidePresetsAreTheFirstSamplers) {
  auto wide = sampler_->Sample(PopulationPreset::kWomenWide, 1, 2);
  ASSERT_TRUE(wide.ok());
  EXPECT_EQ(*wide, SampleBodyParams(PopulationPreset::kWomen, 1, 2));
  EXPECT_THAT(sampler_->SampleCalibrated(PopulationPreset::kMenWide, 1, 2).status(),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "not calibrated"));
}

TEST(SurveyTableTest, CorrelationsAreAValidCorrelationMatrix) {
  for (const SurveyTable* table : {&AnsurWomen(), &AnsurMen()}) {
    Eigen::Matrix<double, kSurveyMeasurementCount, kSurveyMeasurementCount> c;
    for (int i = 0; i < kSurveyMeasurementCount; ++i) {
      for (int j = 0; j < kSurveyMeasurementCount; ++j) c(i, j) = table->correlation[i][j];
    }
    EXPECT_TRUE(c.isApprox(c.transpose()));
    EXPECT_EQ(c.diagonal(), decltype(c)::Identity().diagonal());
    EXPECT_EQ(c.llt().info(), Eigen::Success) << table->name;  // Positive definite.
  }
}

}  // namespace
}  // namespace fitbase::body
