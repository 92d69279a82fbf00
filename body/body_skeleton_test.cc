#include "body/body_skeleton.h"

#include "core/test_support.h"
#include "gtest/gtest.h"

namespace fitbase::body {
namespace {

TEST(BodySkeletonTest, BonesOfTheDefaultHuman) {
  auto model = BodyModel::Load(core::TestDataDir());
  ASSERT_TRUE(model.ok());
  auto full = model->BuildFullMesh(BodyParams{});
  ASSERT_TRUE(full.ok());
  auto bones = BodyBones(*model, full->positions);
  ASSERT_TRUE(bones.ok()) << bones.status();
  EXPECT_EQ(bones->size(), 20u);
  // The spine runs up, the legs down.
  const Bone& spine = bones->front();
  EXPECT_GT(spine.end.y(), spine.start.y());
  const Bone& thigh = NearestBone(*bones, Eigen::Vector3d(0.1, -0.3, 0.0));
  EXPECT_EQ(thigh.region, BodyRegion::kLegs);
  EXPECT_LT(thigh.end.y(), thigh.start.y());
  EXPECT_EQ(NearestBone(*bones, Eigen::Vector3d(0, 0.4, 0)).region, BodyRegion::kTorso);
  EXPECT_EQ(BodyRegionName(BodyRegion::kFeet), "feet");
}

TEST(BodySkeletonTest, NeedsTheFullMesh) {
  auto model = BodyModel::Load(core::TestDataDir());
  ASSERT_TRUE(model.ok());
  EXPECT_EQ(BodyBones(*model, core::Positions::Zero(10, 3)).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_TRUE(model->GroupVertices("no-such-group").empty());
  EXPECT_FALSE(model->GroupVertices("joint-l-knee").empty());
}

}  // namespace
}  // namespace fitbase::body
