#include "proto/avatar_codec.h"

#include <cmath>
#include <limits>
#include <string>

#include "absl/status/status.h"
#include "body/body_model.h"
#include "core/garment_obj.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::proto {
namespace {

using ::fitbase::core::StatusIs;
using ::testing::HasSubstr;

// The hm08 base mesh's body in meters: MakeHuman's model frame, +y up, facing +z.
core::Positions BaseBody() {
  auto base = core::ReadGarmentObj(core::TestDataDir() / "base.obj");
  EXPECT_TRUE(base.ok()) << base.status();
  if (!base.ok()) return {};
  return base->mesh.positions.topRows(body::kBodyVertexCount) * body::kMetersPerDataUnit;
}

class AvatarCodecTest : public ::testing::Test {
 protected:
  void SetUp() override {
    body_ = BaseBody();
    ASSERT_EQ(body_.rows(), body::kBodyVertexCount);
    auto avatar = AvatarFromPositions(body_, /*draco=*/false);
    ASSERT_TRUE(avatar.ok()) << avatar.status();
    raw_ = *avatar;
  }

  // The error AvatarPositions gives for `raw_` changed by `change`.
  template <typename Change>
  absl::Status ErrorAfter(Change change) {
    v1::Avatar avatar = raw_;
    change(avatar);
    return AvatarPositions(avatar).status();
  }

  // The error for `raw_` with its positions replaced by `positions`.
  absl::Status ErrorFor(const core::Positions& positions) {
    return ErrorAfter([&positions](v1::Avatar& avatar) {
      avatar.mutable_positions()->mutable_raw()->clear_xyz();
      for (Eigen::Index i = 0; i < positions.size(); ++i) {
        avatar.mutable_positions()->mutable_raw()->add_xyz(
            static_cast<float>(positions.data()[i]));
      }
    });
  }

  core::Positions body_;
  v1::Avatar raw_;
};

TEST_F(AvatarCodecTest, RawRoundTripIsExactToFloat32) {
  EXPECT_EQ(raw_.format_version(), kAvatarFormatVersion);
  EXPECT_EQ(raw_.topology_id(), "makehuman-hm08-body");
  EXPECT_EQ(raw_.positions().vertex_count(), 13380u);
  EXPECT_FALSE(raw_.has_params());
  EXPECT_FALSE(raw_.has_measurements());
  auto positions = AvatarPositions(raw_);
  ASSERT_TRUE(positions.ok()) << positions.status();
  ASSERT_EQ(positions->rows(), body::kBodyVertexCount);
  for (Eigen::Index i = 0; i < body_.size(); ++i) {
    ASSERT_EQ(positions->data()[i], static_cast<float>(body_.data()[i])) << i;
  }
}

TEST_F(AvatarCodecTest, DracoRoundTripIsWithinTheStatedErrorAndFourTimesSmaller) {
  v1::AvatarParams params;
  params.set_gender(0.2);
  params.set_age_years(40);
  auto avatar = AvatarFromPositions(body_, /*draco=*/true, &params);
  ASSERT_TRUE(avatar.ok()) << avatar.status();
  ASSERT_TRUE(avatar->positions().has_draco());
  EXPECT_EQ(avatar->params().gender(), 0.2);
  EXPECT_FALSE(avatar->params().has_weight());
  EXPECT_GE(raw_.ByteSizeLong(), 4 * avatar->ByteSizeLong());
  const double bound = avatar->positions().draco().max_error_m();
  EXPECT_LT(bound, 0.5e-3);
  auto positions = AvatarPositions(*avatar);
  ASSERT_TRUE(positions.ok()) << positions.status();
  EXPECT_LE((*positions - body_).cwiseAbs().maxCoeff(), bound);
}

TEST_F(AvatarCodecTest, MeasurementsAndParamsInRangeAreAccepted) {
  v1::Avatar avatar = raw_;
  avatar.mutable_measurements()->set_height_m(1.67);
  avatar.mutable_measurements()->set_chest_circumference_m(0.92);
  avatar.mutable_measurements()->set_waist_circumference_m(0.74);
  avatar.mutable_measurements()->set_hip_circumference_m(0.98);
  avatar.mutable_measurements()->set_inseam_m(0.78);
  avatar.mutable_params()->set_weight(0.7);
  EXPECT_TRUE(AvatarPositions(avatar).ok()) << AvatarPositions(avatar).status();
}

TEST_F(AvatarCodecTest, EveryProblemIsNamed) {
  using absl::StatusCode::kInvalidArgument;
  EXPECT_THAT(ErrorAfter([](v1::Avatar& a) { a.set_format_version(0); }),
              StatusIs(kInvalidArgument, "format_version is 0; this reader supports "
                                         "format_version 1"));
  EXPECT_THAT(ErrorAfter([](v1::Avatar& a) { a.set_format_version(2); }),
              StatusIs(kInvalidArgument, "format_version is 2"));
  EXPECT_THAT(ErrorAfter([](v1::Avatar& a) { a.set_topology_id("makehuman-hm08"); }),
              StatusIs(kInvalidArgument,
                       "topology_id is \"makehuman-hm08\"; expected \"makehuman-hm08-body\""));
  EXPECT_THAT(ErrorAfter([](v1::Avatar& a) { a.clear_positions(); }),
              StatusIs(kInvalidArgument, "avatar positions: positions have vertex_count 0"));
  EXPECT_THAT(ErrorAfter([](v1::Avatar& a) { a.mutable_positions()->clear_raw(); }),
              StatusIs(kInvalidArgument, "neither raw nor draco"));
  EXPECT_THAT(ErrorAfter([](v1::Avatar& a) {
                a.mutable_positions()->mutable_raw()->mutable_xyz()->RemoveLast();
              }),
              StatusIs(kInvalidArgument, "40139 values for 13380 vertices"));
  EXPECT_THAT(ErrorAfter([](v1::Avatar& a) {
                const float nan = std::numeric_limits<float>::quiet_NaN();
                a.mutable_positions()->mutable_raw()->set_xyz(3 * 77, nan);
              }),
              StatusIs(kInvalidArgument, "vertex 77 has a non-finite coordinate"));
  EXPECT_THAT(ErrorAfter([](v1::Avatar& a) {
                a.mutable_positions()->mutable_draco()->set_data("garbage");
              }),
              StatusIs(kInvalidArgument, "avatar positions: Draco positions (7 bytes) are not"));

  EXPECT_THAT(ErrorFor(body_ * 10), StatusIs(kInvalidArgument, "looks like decimeters"));
  EXPECT_THAT(ErrorFor(body_ * 100), StatusIs(kInvalidArgument, "looks like centimeters"));
  EXPECT_THAT(ErrorFor(body_ * 1000), StatusIs(kInvalidArgument, "looks like millimeters"));
  core::Positions lying = body_;
  lying.col(1).swap(lying.col(2));
  EXPECT_THAT(ErrorFor(lying), StatusIs(kInvalidArgument, "tall along +y; positions are meters "
                                                          "with +y up"));
  core::Positions on_the_ground = body_;
  on_the_ground.col(1).array() -= body_.col(1).minCoeff();
  EXPECT_THAT(ErrorFor(on_the_ground),
              StatusIs(kInvalidArgument, "not with the feet on the ground"));

  EXPECT_THAT(ErrorAfter([](v1::Avatar& a) {
                a.mutable_measurements()->set_chest_circumference_m(95);
              }),
              StatusIs(kInvalidArgument, "measurements.chest_circumference_m is 95; expected 0.2 "
                                         "to 3 (meters); it looks like centimeters"));
  EXPECT_THAT(ErrorAfter([](v1::Avatar& a) { a.mutable_measurements()->set_height_m(0); }),
              StatusIs(kInvalidArgument, "height_m is 0"));
  EXPECT_THAT(ErrorAfter([](v1::Avatar& a) { a.mutable_measurements()->set_inseam_m(-0.8); }),
              StatusIs(kInvalidArgument, "inseam_m is -0.8"));
  EXPECT_THAT(ErrorAfter([](v1::Avatar& a) {
                a.mutable_measurements()->set_waist_circumference_m(
                    std::numeric_limits<double>::quiet_NaN());
              }),
              StatusIs(kInvalidArgument, "waist_circumference_m is nan"));
  EXPECT_THAT(ErrorAfter([](v1::Avatar& a) {
                a.mutable_measurements()->set_hip_circumference_m(4);
              }),
              StatusIs(kInvalidArgument, "hip_circumference_m is 4"));
  EXPECT_THAT(ErrorAfter([](v1::Avatar& a) { a.mutable_params()->set_gender(1.5); }),
              StatusIs(kInvalidArgument, "avatar params: "));
}

TEST_F(AvatarCodecTest, WritingRefusesWhatReadingWould) {
  EXPECT_THAT(AvatarFromPositions(body_.topRows(100), false),
              StatusIs(absl::StatusCode::kInvalidArgument, "avatar has 100 vertices"));
  EXPECT_THAT(AvatarFromPositions(body_ * 10, true),
              StatusIs(absl::StatusCode::kInvalidArgument, "looks like decimeters"));
  v1::AvatarParams params;
  params.set_age_years(12);
  const absl::Status status = AvatarFromPositions(body_, false, &params).status();
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(status.message()), HasSubstr("age_years"));
}

}  // namespace
}  // namespace fitbase::proto
