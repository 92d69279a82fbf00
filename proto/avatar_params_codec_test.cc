#include "proto/avatar_params_codec.h"

#include <limits>
#include <string>

#include "absl/status/status.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::proto {
namespace {

using ::testing::HasSubstr;

constexpr char kWaist[] = "measure/measure-waist-circ-decr|incr";
constexpr char kHips[] = "hip/hip-scale-depth-decr|incr";

body::BodyParams NonDefaultParams() {
  body::BodyParams p;
  p.gender = 0.1;
  p.age_years = 47.5;
  p.muscle = 0.3;
  p.weight = 0.8;
  p.height = 0.25;
  p.proportions = 0.6;
  p.african = 0.2;
  p.asian = 0.5;
  p.caucasian = 0.3;
  p.breast_size = 0.9;
  p.breast_firmness = 0.05;
  p.modifiers[kWaist] = -0.4;
  p.modifiers["breast/breast-dist-decr|incr"] = 1.0;
  return p;
}

void ExpectInvalid(const v1::AvatarParams& message, const std::string& needle) {
  EXPECT_THAT(BodyParamsFromProto(message), core::StatusIs(absl::StatusCode::kInvalidArgument, needle));
}

TEST(AvatarParamsCodecTest, EmptyMessageIsTheDefaultHuman) {
  auto params = BodyParamsFromProto(v1::AvatarParams());
  ASSERT_TRUE(params.ok()) << params.status();
  EXPECT_EQ(*params, body::BodyParams{});
}

TEST(AvatarParamsCodecTest, UnsetFieldsTakeDefaultsAndSetOnesAreKept) {
  v1::AvatarParams message;
  message.set_gender(0.0);  // Explicit zero must not be mistaken for "unset".
  message.set_age_years(60.0);
  auto params = BodyParamsFromProto(message);
  ASSERT_TRUE(params.ok()) << params.status();
  body::BodyParams expected;
  expected.gender = 0.0;
  expected.age_years = 60.0;
  EXPECT_EQ(*params, expected);
}

TEST(AvatarParamsCodecTest, ToProtoSetsEveryField) {
  const v1::AvatarParams message = BodyParamsToProto(body::BodyParams{});
  EXPECT_TRUE(message.has_gender());
  EXPECT_TRUE(message.has_age_years());
  EXPECT_TRUE(message.has_muscle());
  EXPECT_TRUE(message.has_weight());
  EXPECT_TRUE(message.has_height());
  EXPECT_TRUE(message.has_proportions());
  EXPECT_TRUE(message.has_african());
  EXPECT_TRUE(message.has_asian());
  EXPECT_TRUE(message.has_caucasian());
  EXPECT_TRUE(message.has_breast_size());
  EXPECT_TRUE(message.has_breast_firmness());
  EXPECT_EQ(message.age_years(), 25.0);
  EXPECT_EQ(message.caucasian(), 1.0 / 3.0);
}

TEST(AvatarParamsCodecTest, RoundTripIsExact) {
  const body::BodyParams original = NonDefaultParams();
  const v1::AvatarParams message = BodyParamsToProto(original);
  EXPECT_EQ(message.gender(), 0.1);
  EXPECT_EQ(message.modifiers().at(kWaist), -0.4);
  EXPECT_EQ(message.modifiers_size(), 2);
  auto decoded = BodyParamsFromProto(message);
  ASSERT_TRUE(decoded.ok()) << decoded.status();
  EXPECT_EQ(*decoded, original);
}

TEST(AvatarParamsCodecTest, RejectsOutOfRangeMacroNamingIt) {
  v1::AvatarParams message;
  message.set_muscle(1.5);
  ExpectInvalid(message, "'muscle'");

  message.Clear();
  message.set_breast_firmness(-0.01);
  ExpectInvalid(message, "'breast_firmness'");

  message.Clear();
  message.set_height(std::numeric_limits<double>::quiet_NaN());
  ExpectInvalid(message, "'height'");
}

TEST(AvatarParamsCodecTest, RejectsAgeOutsideAdultRange) {
  v1::AvatarParams message;
  message.set_age_years(24.0);
  ExpectInvalid(message, "'age_years'");
  message.set_age_years(91.0);
  ExpectInvalid(message, "'age_years'");
}

TEST(AvatarParamsCodecTest, RejectsEthnicSharesNotSummingToOne) {
  v1::AvatarParams message;
  message.set_african(1.0);  // Asian and caucasian default to 1/3 each.
  ExpectInvalid(message, "ethnic shares");
}

TEST(AvatarParamsCodecTest, RejectsOutOfRangeModifierNamingIt) {
  v1::AvatarParams message;
  (*message.mutable_modifiers())[kHips] = 1.25;
  ExpectInvalid(message, kHips);
}

TEST(AvatarParamsCodecTest, RejectsUnknownModifierNamingIt) {
  v1::AvatarParams message;
  (*message.mutable_modifiers())["measure/measure-waist-circ"] = 0.2;  // Missing the suffix.
  ExpectInvalid(message, "unknown modifier 'measure/measure-waist-circ'");
}

}  // namespace
}  // namespace fitbase::proto
