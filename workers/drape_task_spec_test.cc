#include "workers/drape_task_spec.h"

#include <cmath>
#include <limits>

#include "body/body_model.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::workers {
namespace {

class DrapeTaskSpecTest : public ::testing::Test {
 protected:
  DrapeTaskSpecTest() {
    garment_.set_id("garment-1");
    body_ = core::Positions(body::kBodyVertexCount, 3);
    for (Eigen::Index i = 0; i < body_.size(); ++i) body_.data()[i] = std::sin(0.1 * i);
  }
  v1::Garment garment_;
  core::Positions body_;
};

TEST_F(DrapeTaskSpecTest, RoundTripKeepsTheKeyAndEveryInput) {
  ClothSettings settings;
  settings.contact_stiffness = 3e7;
  settings.newton_tolerance = 3e-5;
  settings.path_newton_iterations = 7;
  settings.compression_stiffness = 150;
  settings.area_floor = 0.3;
  settings.waistband_on_rise = false;
  const DrapeTask task = MakeDrapeTask(garment_, "XL", body_, settings, {7, 9});
  // The key names every setting, this one too.
  ClothSettings on_rise = settings;
  on_rise.waistband_on_rise = true;
  EXPECT_NE(task.key, MakeDrapeTask(garment_, "XL", body_, on_rise, {7, 9}).key);
  ClothSettings cuff_friction = settings;
  cuff_friction.cuff_friction = 0.5;
  const DrapeTask with_cuff_friction = MakeDrapeTask(garment_, "XL", body_, cuff_friction, {7, 9});
  EXPECT_NE(task.key, with_cuff_friction.key);
  absl::StatusOr<DrapeTask> parsed_cuff_friction =
      DrapeTaskFromSpec(DrapeTaskToSpec(with_cuff_friction));
  ASSERT_TRUE(parsed_cuff_friction.ok()) << parsed_cuff_friction.status();
  EXPECT_EQ(parsed_cuff_friction->settings.cuff_friction, 0.5);
  EXPECT_EQ(parsed_cuff_friction->key, with_cuff_friction.key);
  const v1::DrapeTaskSpec spec = DrapeTaskToSpec(task);
  absl::StatusOr<DrapeTask> parsed = DrapeTaskFromSpec(spec);
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  const DrapeTask& back = *parsed;
  EXPECT_EQ(back.key, task.key);
  EXPECT_EQ(back.size, "XL");
  EXPECT_EQ(back.garment, &spec.garment());
  EXPECT_EQ(back.body, task.body);
  EXPECT_EQ(back.settings.contact_stiffness, 3e7);
  EXPECT_EQ(back.settings.newton_tolerance, 3e-5);
  EXPECT_EQ(back.settings.path_newton_iterations, 7);
  EXPECT_EQ(back.settings.compression_stiffness, 150);
  EXPECT_EQ(back.settings.area_floor, 0.3);
  EXPECT_FALSE(back.settings.waistband_on_rise);
  EXPECT_EQ(back.schedule.homotopy_steps, 7);
  EXPECT_EQ(back.schedule.relax_steps, 9);
}

TEST_F(DrapeTaskSpecTest, RefusesASpecWhoseContentDoesNotHashToItsKey) {
  v1::DrapeTaskSpec spec = DrapeTaskToSpec(MakeDrapeTask(garment_, "M", body_));
  spec.set_body(100, spec.body(100) + 0.01f);
  EXPECT_THAT(DrapeTaskFromSpec(spec),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "hashes to"));
}

TEST_F(DrapeTaskSpecTest, RefusesBadBodiesAndSettingsNamingTheProblem) {
  const v1::DrapeTaskSpec good = DrapeTaskToSpec(MakeDrapeTask(garment_, "M", body_));
  v1::DrapeTaskSpec spec = good;
  spec.mutable_body()->RemoveLast();
  EXPECT_THAT(DrapeTaskFromSpec(spec),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "40139 coordinates"));
  spec = good;
  spec.set_body(5, std::numeric_limits<float>::quiet_NaN());
  EXPECT_THAT(DrapeTaskFromSpec(spec),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "non-finite"));
  spec = good;
  spec.mutable_settings()->set_step_seconds(std::numeric_limits<double>::infinity());
  EXPECT_THAT(DrapeTaskFromSpec(spec),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "step_seconds"));
  spec = good;
  spec.mutable_settings()->set_newton_iterations(0);
  EXPECT_THAT(DrapeTaskFromSpec(spec),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "newton_iterations"));
  spec = good;
  spec.mutable_settings()->set_path_newton_iterations(0);
  EXPECT_THAT(DrapeTaskFromSpec(spec),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "path_newton_iterations"));
  spec = good;
  spec.mutable_settings()->set_newton_tolerance(-1e-4);
  EXPECT_THAT(DrapeTaskFromSpec(spec),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "newton_tolerance"));
  spec = good;
  spec.mutable_settings()->set_compression_stiffness(0);
  EXPECT_THAT(DrapeTaskFromSpec(spec),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "compression_stiffness"));
  spec = good;
  spec.mutable_settings()->set_area_floor(1.5);
  EXPECT_THAT(DrapeTaskFromSpec(spec),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "area_floor"));
  spec = good;
  spec.mutable_settings()->set_friction(std::numeric_limits<double>::quiet_NaN());
  EXPECT_THAT(DrapeTaskFromSpec(spec),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "friction"));
  spec = good;
  spec.mutable_settings()->set_friction(1e6);
  EXPECT_THAT(DrapeTaskFromSpec(spec),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "friction = 1e+06 is over 10"));
  spec = good;
  spec.mutable_settings()->set_cuff_friction(-0.5);
  EXPECT_THAT(DrapeTaskFromSpec(spec),
              core::StatusIs(absl::StatusCode::kInvalidArgument,
                             "cuff_friction = -0.5 must be finite and not negative"));
  spec = good;
  spec.mutable_settings()->set_skin_tie(std::numeric_limits<double>::infinity());
  EXPECT_THAT(DrapeTaskFromSpec(spec),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "skin_tie"));
  spec = good;
  spec.mutable_settings()->set_skin_tie(1e9);
  EXPECT_THAT(DrapeTaskFromSpec(spec),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "skin_tie = 1e+09 is over 1e+07"));
  spec = good;
  spec.mutable_settings()->set_relax_steps(1000000);
  EXPECT_THAT(DrapeTaskFromSpec(spec),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "relax_steps"));
}

}  // namespace
}  // namespace fitbase::workers
