#include "body/body_params.h"

#include <cmath>

#include "core/test_support.h"
#include "gtest/gtest.h"

namespace fitbase::body {
namespace {

void ExpectInvalid(const BodyParams& p, const std::string& names) {
  EXPECT_THAT(ValidateBodyParams(p), core::StatusIs(absl::StatusCode::kInvalidArgument, names));
}

TEST(BodyParamsTest, DefaultsAreValid) { EXPECT_TRUE(ValidateBodyParams(BodyParams{}).ok()); }

TEST(BodyParamsTest, AgeMapsToMakeHumanValue) {
  EXPECT_DOUBLE_EQ(AgeValueFromYears(25), 0.5);
  EXPECT_DOUBLE_EQ(AgeValueFromYears(90), 1.0);
  EXPECT_DOUBLE_EQ(AgeValueFromYears(57.5), 0.75);
}

TEST(BodyParamsTest, RangesAreChecked) {
  BodyParams p;
  p.muscle = 1.01;
  ExpectInvalid(p, "muscle");
  p = {};
  p.height = -0.1;
  ExpectInvalid(p, "height");
  p = {};
  p.age_years = 24;
  ExpectInvalid(p, "age_years");
  p = {};
  p.age_years = 91;
  ExpectInvalid(p, "age_years");
  p = {};
  p.gender = std::nan("");
  ExpectInvalid(p, "gender");
  p = {};
  p.breast_size = INFINITY;
  ExpectInvalid(p, "breast_size");
}

TEST(BodyParamsTest, EthnicSharesMustSumToOne) {
  BodyParams p;
  p.african = 0.5;
  ExpectInvalid(p, "ethnic");
  p.asian = 0.25;
  p.caucasian = 0.25;
  EXPECT_TRUE(ValidateBodyParams(p).ok());
}

TEST(BodyParamsTest, ModifiersByNameAndRange) {
  BodyParams p;
  p.modifiers["measure/measure-waist-circ-decr|incr"] = -1;
  p.modifiers["breast/breast-trans-down|up"] = 1;
  EXPECT_TRUE(ValidateBodyParams(p).ok());
  p.modifiers["measure/measure-waist-circ-decr|incr"] = -1.5;
  ExpectInvalid(p, "measure/measure-waist-circ-decr|incr");
  p = {};
  p.modifiers["head/head-age-decr|incr"] = 0.2;
  ExpectInvalid(p, "unknown modifier 'head/head-age-decr|incr'");
}

TEST(BodyParamsTest, ModifierTableCoversTheBodyGroups) {
  EXPECT_EQ(LocalModifiers().size(), 47u);
  const LocalModifier* waist = FindLocalModifier("measure/measure-waist-circ-decr|incr");
  ASSERT_NE(waist, nullptr);
  EXPECT_EQ(waist->decrease_target, "measure/measure-waist-circ-decr.target");
  EXPECT_EQ(waist->increase_target, "measure/measure-waist-circ-incr.target");
  EXPECT_EQ(FindLocalModifier("measure-waist"), nullptr);
}

}  // namespace
}  // namespace fitbase::body
