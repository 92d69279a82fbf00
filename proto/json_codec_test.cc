#include "proto/json_codec.h"

#include <string>
#include <vector>

#include "absl/status/status.h"
#include "fitbase/v1/avatar.pb.h"
#include "fitbase/v1/avatar_basis.pb.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::proto {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

constexpr char kWaist[] = "measure/measure-waist-circ-decr|incr";

TEST(JsonCodecTest, ParsesAvatarParamsWithSnakeCaseNamesAndModifiers) {
  v1::AvatarParams message;
  const std::string json = R"({"gender": 0.1, "age_years": 40, "breast_size": 0.7,
      "modifiers": {"measure/measure-waist-circ-decr|incr": 0.3,
                    "hip/hip-scale-depth-decr|incr": -0.5}})";
  ASSERT_TRUE(ParseJson(json, &message).ok());
  EXPECT_TRUE(message.has_gender());
  EXPECT_EQ(message.gender(), 0.1);
  EXPECT_EQ(message.age_years(), 40.0);
  EXPECT_EQ(message.breast_size(), 0.7);
  EXPECT_FALSE(message.has_muscle());
  ASSERT_EQ(message.modifiers_size(), 2);
  EXPECT_EQ(message.modifiers().at(kWaist), 0.3);
  EXPECT_EQ(message.modifiers().at("hip/hip-scale-depth-decr|incr"), -0.5);
}

TEST(JsonCodecTest, UnknownFieldIsAnError) {
  v1::AvatarParams message;
  const absl::Status status = ParseJson(R"({"gender": 0.1, "age": 40})", &message);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(status.message()), HasSubstr("fitbase.v1.AvatarParams"));
  EXPECT_THAT(std::string(status.message()), HasSubstr("age"));
}

TEST(JsonCodecTest, MalformedJsonIsAnError) {
  v1::AvatarParams message;
  const absl::Status status = ParseJson(R"({"gender": )", &message);
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
}

TEST(JsonCodecTest, WrongValueTypeIsAnError) {
  v1::AvatarParams message;
  const absl::Status status = ParseJson(R"({"gender": "female"})", &message);
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
}

TEST(JsonCodecTest, ToJsonIsDeterministicWithMapKeysSorted) {
  const std::vector<std::string> names = {
      "stomach/stomach-pregnant-decr|incr", kWaist, "breast/breast-dist-decr|incr",
      "hip/hip-scale-depth-decr|incr", "buttocks/buttocks-volume-decr|incr",
      "measure/measure-neck-circ-decr|incr"};
  v1::AvatarParams forward;
  v1::AvatarParams backward;
  forward.set_gender(0.25);
  backward.set_gender(0.25);
  for (size_t i = 0; i < names.size(); ++i) {
    (*forward.mutable_modifiers())[names[i]] = 0.1 * static_cast<double>(i);
  }
  for (size_t i = names.size(); i-- > 0;) {
    (*backward.mutable_modifiers())[names[i]] = 0.1 * static_cast<double>(i);
  }
  const std::string json = ToJson(forward);
  EXPECT_EQ(json, ToJson(backward));
  EXPECT_EQ(json, ToJson(forward));
  EXPECT_THAT(json, Not(HasSubstr("\n")));

  const std::vector<std::string> sorted = {
      "breast/breast-dist-decr|incr",       "buttocks/buttocks-volume-decr|incr",
      "hip/hip-scale-depth-decr|incr",      "measure/measure-neck-circ-decr|incr",
      "measure/measure-waist-circ-decr|incr", "stomach/stomach-pregnant-decr|incr"};
  size_t previous = 0;
  for (const std::string& name : sorted) {
    const size_t position = json.find("\"" + name + "\"");
    ASSERT_NE(position, std::string::npos) << name << " missing from " << json;
    EXPECT_GT(position, previous) << name << " out of order in " << json;
    previous = position;
  }

  // And the bytes parse back to the same message.
  v1::AvatarParams parsed;
  ASSERT_TRUE(ParseJson(json, &parsed).ok());
  EXPECT_EQ(parsed.gender(), 0.25);
  ASSERT_EQ(parsed.modifiers_size(), static_cast<int>(names.size()));
  for (size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(parsed.modifiers().at(names[i]), 0.1 * static_cast<double>(i)) << names[i];
  }
}

TEST(JsonCodecTest, ToJsonKeepsOptionalFieldsUnset) {
  // Printing every field must not turn an unset optional parameter into an explicit 0.
  v1::AvatarParams message;
  message.set_age_years(40.0);
  const std::string json = ToJson(message);
  EXPECT_THAT(json, HasSubstr("\"age_years\":40"));
  EXPECT_THAT(json, Not(HasSubstr("gender")));
  EXPECT_THAT(json, Not(HasSubstr("caucasian")));
  v1::AvatarParams parsed;
  ASSERT_TRUE(ParseJson(json, &parsed).ok()) << json;
  EXPECT_TRUE(parsed.has_age_years());
  EXPECT_FALSE(parsed.has_gender());
  EXPECT_FALSE(parsed.has_caucasian());
}

TEST(JsonCodecTest, ToJsonUsesProtoFieldNamesAndPrintsDefaults) {
  v1::AvatarWeights weights;
  weights.set_basis_id("abc");
  weights.add_weights(0.5);
  weights.add_weights(-0.25);
  weights.set_mean_error_mm(1.5);
  // max_error_mm stays 0: printed anyway, so every file lists every field.
  const std::string json = ToJson(weights);
  EXPECT_THAT(json, HasSubstr("\"basis_id\":\"abc\""));
  EXPECT_THAT(json, HasSubstr("\"mean_error_mm\":1.5"));
  EXPECT_THAT(json, HasSubstr("\"max_error_mm\":0"));
  EXPECT_THAT(json, HasSubstr("\"weights\":[0.5,-0.25]"));
  EXPECT_THAT(json, Not(HasSubstr("meanErrorMm")));
  EXPECT_THAT(json, Not(HasSubstr("basisId")));
}

TEST(JsonCodecTest, ToJsonThenParseJsonRoundTripsNestedMessages) {
  v1::PopulationProvenance provenance;
  provenance.set_preset("women");
  provenance.set_seed(18446744073709551615ull);  // uint64 max: JSON prints it as a string.
  provenance.set_count(3);
  provenance.add_params()->set_age_years(33.0);
  const std::string json = ToJson(provenance);
  EXPECT_THAT(json, HasSubstr("\"age_years\":33"));
  v1::PopulationProvenance parsed;
  ASSERT_TRUE(ParseJson(json, &parsed).ok()) << json;
  EXPECT_EQ(parsed.preset(), "women");
  EXPECT_EQ(parsed.seed(), 18446744073709551615ull);
  EXPECT_EQ(parsed.count(), 3u);
  ASSERT_EQ(parsed.params_size(), 1);
  EXPECT_EQ(parsed.params(0).age_years(), 33.0);
  EXPECT_FALSE(parsed.params(0).has_gender());
}

}  // namespace
}  // namespace fitbase::proto
