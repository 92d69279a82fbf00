#include "clothing/size_advice.h"

#include <string>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::clothing {
namespace {

using ::testing::HasSubstr;

RegionFitValue Girth(FitRegion region, double ease_cm) {
  return {.region = region, .body_cm = 90, .garment_cm = 90 + ease_cm, .ease_cm = ease_cm};
}

TEST(SizeAdviceTest, ShirtBustVerdictsFollowTheBandEdges) {
  // Shirt at the bust: tight below +2, fitted to +6, regular to +12, loose beyond.
  std::vector<RegionFitValue> values = {Girth(FitRegion::kBust, 1.9), Girth(FitRegion::kBust, 2),
                                        Girth(FitRegion::kBust, 6), Girth(FitRegion::kBust, 12),
                                        Girth(FitRegion::kBust, 12.1)};
  JudgeRegions(GarmentType::kShirt, values);
  EXPECT_EQ(values[0].verdict, Verdict::kTight);
  EXPECT_EQ(values[1].verdict, Verdict::kFitted);
  EXPECT_EQ(values[2].verdict, Verdict::kRegular);
  EXPECT_EQ(values[3].verdict, Verdict::kRegular);
  EXPECT_EQ(values[4].verdict, Verdict::kLoose);
}

TEST(SizeAdviceTest, KnitsAreRegularWithNegativeEase) {
  std::vector<RegionFitValue> values = {Girth(FitRegion::kHip, -2.5)};
  JudgeRegions(GarmentType::kKnit, values);
  EXPECT_EQ(values[0].verdict, Verdict::kRegular);
  JudgeRegions(GarmentType::kJacket, values);
  EXPECT_EQ(values[0].verdict, Verdict::kTight);
}

TEST(SizeAdviceTest, LengthsAreJudgedAgainstTheirDesignEase) {
  std::vector<RegionFitValue> values = {
      {.region = FitRegion::kSleeveLength, .ease_cm = -8, .design_ease_cm = -4},
      {.region = FitRegion::kGarmentLength, .ease_cm = 2, .design_ease_cm = -2},
      {.region = FitRegion::kGarmentLength, .ease_cm = -4, .design_ease_cm = -2}};
  JudgeRegions(GarmentType::kShirt, values);
  EXPECT_EQ(values[0].verdict, Verdict::kShort);
  EXPECT_EQ(values[1].verdict, Verdict::kLong);
  EXPECT_EQ(values[2].verdict, Verdict::kRegular);
}

TEST(SizeAdviceTest, RecommendsTheRegularSizeAndSaysWhyTheOthersAreNot) {
  const std::vector<std::string> names = {"S", "M", "L"};
  std::vector<std::vector<RegionFitValue>> sizes = {
      {Girth(FitRegion::kBust, -2.1), Girth(FitRegion::kWaist, 3)},
      {Girth(FitRegion::kBust, 7), Girth(FitRegion::kWaist, 9)},
      {Girth(FitRegion::kBust, 13), Girth(FitRegion::kWaist, 16.5)}};
  for (auto& size : sizes) JudgeRegions(GarmentType::kShirt, size);
  const SizeRecommendation advice = RecommendSize(GarmentType::kShirt, names, sizes);
  ASSERT_EQ(advice.best, 1);
  EXPECT_EQ(advice.summaries[0], "S: tight at the bust (\u22122.1 cm); fitted at the waist (+3.0 cm)");
  EXPECT_EQ(advice.summaries[1], "M: regular fit");
  EXPECT_EQ(advice.summaries[2], "L: loose at the waist (+16.5 cm), bust (+13.0 cm)");
  EXPECT_EQ(advice.overall[0], Verdict::kTight);
  EXPECT_EQ(advice.overall[2], Verdict::kLoose);
  // The next best, L, is 3.5 cm out of its bands.
  EXPECT_NEAR(advice.confidence, 1 - 0.5 * std::exp(-3.5 / 2), 1e-12);
  ASSERT_EQ(advice.reasons.size(), 3u);
  EXPECT_THAT(advice.reasons[0], HasSubstr("M has the ease a shirt is cut with"));
}

TEST(SizeAdviceTest, TwoSizesOutOfBandTheCloserWinsAtLowConfidence) {
  const std::vector<std::string> names = {"M", "L"};
  std::vector<std::vector<RegionFitValue>> sizes = {{Girth(FitRegion::kBust, 1.0)},
                                                    {Girth(FitRegion::kBust, 16.0)}};
  for (auto& size : sizes) JudgeRegions(GarmentType::kShirt, size);
  // M: 5 cm below regular, 3 x 1 cm below tight = 8; L: 4 cm above loose.
  const SizeRecommendation advice = RecommendSize(GarmentType::kShirt, names, sizes);
  EXPECT_EQ(advice.best, 1);
  EXPECT_NEAR(advice.confidence, 1 - 0.5 * std::exp(-2.0), 1e-12);
  EXPECT_THAT(advice.reasons[0], HasSubstr("the closest of the sizes"));
}

TEST(SizeAdviceTest, ParsesTypesAndNamesTheKnownOnes) {
  EXPECT_EQ(*ParseGarmentType("jacket"), GarmentType::kJacket);
  const auto bad = ParseGarmentType("tuxedo");
  ASSERT_FALSE(bad.ok());
  EXPECT_THAT(bad.status().message(), HasSubstr("knit, fitted, shirt, jacket"));
}

}  // namespace
}  // namespace fitbase::clothing
