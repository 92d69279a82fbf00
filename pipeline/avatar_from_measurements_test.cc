#include "pipeline/avatar_from_measurements.h"

#include <cmath>
#include <limits>

#include "body/body_model.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "pipeline/avatar_basis_builder.h"
#include "pipeline/population_folder.h"
#include "proto/avatar_basis_codec.h"

namespace fitbase::pipeline {
namespace {

using body::Measurement;
using core::StatusIs;

class AvatarFromMeasurementsTest : public ::testing::Test {
 protected:
  // A women's basis of 60 calibrated avatars, and 4 held-out women: small, but the same code
  // path as a shop's basis.
  static void SetUpTestSuite() {
    auto model = body::BodyModel::Load(core::TestDataDir());
    ASSERT_TRUE(model.ok()) << model.status();
    auto population = SamplePopulation(*model, body::PopulationPreset::kWomen, 1, 60);
    ASSERT_TRUE(population.ok()) << population.status();
    core::ComponentSelection selection;
    selection.max_mean_error_mm = 2.0;
    auto message = BuildAvatarBasis(*population, selection);
    ASSERT_TRUE(message.ok()) << message.status();
    basis_ = new LoadedAvatarBasis{.message = *message, .pca = {}};
    auto pca = proto::PcaBasisFromProto(*message);
    ASSERT_TRUE(pca.ok());
    basis_->pca = *std::move(pca);
    auto measurement_model = MeasurementModel::Build(*basis_);
    ASSERT_TRUE(measurement_model.ok()) << measurement_model.status();
    model_ = new MeasurementModel(*std::move(measurement_model));
    auto holdout = SamplePopulation(*model, body::PopulationPreset::kWomen, 2, 4);
    ASSERT_TRUE(holdout.ok());
    holdout_ = new Population(*std::move(holdout));
  }
  static body::BodyMeasurements TrueMeasurements(int i) {
    const core::Positions positions = Eigen::Map<const core::Positions>(
        holdout_->samples.col(i).data(), body::kBodyVertexCount, 3);
    auto m = body::MeasureBody(positions, model_->triangles(), body::AllMeasurements());
    EXPECT_TRUE(m.ok()) << m.status();
    return *m;
  }
  static LoadedAvatarBasis* basis_;
  static MeasurementModel* model_;
  static Population* holdout_;
};
LoadedAvatarBasis* AvatarFromMeasurementsTest::basis_ = nullptr;
MeasurementModel* AvatarFromMeasurementsTest::model_ = nullptr;
Population* AvatarFromMeasurementsTest::holdout_ = nullptr;

TEST_F(AvatarFromMeasurementsTest, GivenMeasurementsComeBackWithinTheirAllowance) {
  int within = 0, total = 0;
  for (int i = 0; i < 4; ++i) {
    const body::BodyMeasurements truth = TrueMeasurements(i);
    MeasurementSet given;
    for (Measurement m : {Measurement::kStature, Measurement::kWeight, Measurement::kBustGirth,
                          Measurement::kWaistGirth, Measurement::kHipGirth}) {
      given.emplace_back(m, truth[static_cast<int>(m)]);
    }
    auto made = AvatarFromMeasurements(*basis_, *model_, given);
    ASSERT_TRUE(made.ok()) << made.status();
    ASSERT_EQ(made->avatar.vertex_count(), body::kBodyVertexCount);
    ASSERT_EQ(made->residuals.size(), given.size());
    for (const auto& [m, value, reached] : made->residuals) {
      ++total;
      within += std::abs(reached - value) <= MeasurementAllowance(m);
    }
    // The made body is the one its residuals were measured on.
    auto remeasured = body::MeasureBody(made->avatar);
    ASSERT_TRUE(remeasured.ok());
    EXPECT_NEAR((*remeasured)[0], std::get<2>(made->residuals[0]), 1e-9);
  }
  EXPECT_GE(within, total - 1);
}

TEST_F(AvatarFromMeasurementsTest, AnImpossibleBodyGetsItsBestAvatarAndTheReasons) {
  // 150 cm with a 160 cm hip: no woman of the population.
  const MeasurementSet given = {{Measurement::kStature, 1.50}, {Measurement::kHipGirth, 1.60}};
  auto made = AvatarFromMeasurements(*basis_, *model_, given);
  ASSERT_TRUE(made.ok()) << made.status();
  EXPECT_THAT(made->out_of_distribution_reasons,
              ::testing::Contains(::testing::HasSubstr("hip_girth")));
}

TEST(MeasurementsFromProtoTest, NamesEachBadField) {
  v1::TypedMeasurements typed;
  EXPECT_THAT(MeasurementsFromProto(typed).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, "no measurements"));
  typed.set_weight_kg(60);
  EXPECT_THAT(MeasurementsFromProto(typed).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, "stature_cm is required"));
  typed.set_stature_cm(40);
  EXPECT_THAT(MeasurementsFromProto(typed).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, "stature_cm is 40"));
  typed.set_stature_cm(std::numeric_limits<double>::quiet_NaN());
  EXPECT_THAT(MeasurementsFromProto(typed).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, "stature_cm is not a finite"));
  typed.set_stature_cm(170);
  typed.set_hip_girth_cm(-3);
  EXPECT_THAT(MeasurementsFromProto(typed).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, "hip_girth_cm is -3"));
  typed.set_hip_girth_cm(98);
  auto set = MeasurementsFromProto(typed);
  ASSERT_TRUE(set.ok()) << set.status();
  ASSERT_EQ(set->size(), 3u);
  EXPECT_DOUBLE_EQ((*set)[0].second, 1.70);  // Meters inside.
  EXPECT_DOUBLE_EQ((*set)[1].second, 60);    // Kilograms.
}

TEST(MeasurementsFromProtoTest, RoundTripsWhatMeasureBodyGives) {
  body::BodyMeasurements m;
  for (int i = 0; i < body::kMeasurementCount; ++i) m[i] = 0.5 + 0.01 * i;
  m[static_cast<int>(Measurement::kStature)] = 1.7;
  m[static_cast<int>(Measurement::kWeight)] = 70;
  const v1::TypedMeasurements typed = MeasurementsToProto(m);
  EXPECT_DOUBLE_EQ(typed.stature_cm(), 170);
  EXPECT_DOUBLE_EQ(typed.weight_kg(), 70);
}

}  // namespace
}  // namespace fitbase::pipeline
