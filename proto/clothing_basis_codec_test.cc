#include "proto/clothing_basis_codec.h"

#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::proto {
namespace {

core::ClothingModel SmallModel() {
  core::ClothingModel model;
  model.method = core::ClothingMethod::kQuadratic;
  model.component_count = 2;
  model.basis = Eigen::MatrixXf::Random(6, 5);
  model.term_component = {0, 1, 0, 1};
  model.term_power = {1, 1, 2, 2};
  return model;
}

core::BodyCorrespondence SmallCorrespondence() {
  core::BodyCorrespondence c;
  c.offset = 0.0025;
  c.anchors_per_vertex = 2;
  c.body_vertices = {3, 7, 9, 12};
  c.body_mean = Eigen::VectorXf::Random(12);
  c.body_components = Eigen::MatrixXf::Random(12, 2);
  c.corners.resize(4, 3);
  c.corners << 0, 1, 2, 1, 2, 3, 0, 1, 3, 0, 2, 3;
  c.barycentric.resize(4, 3);
  c.barycentric << 0.2f, 0.3f, 0.5f, 1, 0, 0, 0, 1, 0, 0.5f, 0.5f, 0;
  return c;
}

TEST(ClothingBasisCodecTest, RoundTripsModelAndCorrespondence) {
  const core::ClothingModel original = SmallModel();
  const core::BodyCorrespondence original_correspondence = SmallCorrespondence();
  v1::ClothingBasis message;
  ClothingModelToProto(original, &message);
  BodyCorrespondenceToProto(original_correspondence, message.mutable_correspondence());
  EXPECT_EQ(message.method(), "quadratic");
  EXPECT_EQ(message.vertex_count(), 2u);
  const core::ClothingModel model = *ClothingModelFromProto(message);
  EXPECT_EQ(model.basis, original.basis);
  EXPECT_EQ(model.term_power, original.term_power);
  const core::BodyCorrespondence c = *BodyCorrespondenceFromProto(message);
  EXPECT_EQ(c.corners, original_correspondence.corners);
  EXPECT_EQ(c.barycentric, original_correspondence.barycentric);
  EXPECT_EQ(c.body_components, original_correspondence.body_components);
  EXPECT_EQ(c.body_vertices, original_correspondence.body_vertices);
}

TEST(ClothingBasisCodecTest, RejectsInconsistentMessages) {
  v1::ClothingBasis message;
  ClothingModelToProto(SmallModel(), &message);
  BodyCorrespondenceToProto(SmallCorrespondence(), message.mutable_correspondence());
  message.set_id("cb1");
  v1::ClothingBasis short_terms = message;
  short_terms.mutable_terms()->RemoveLast();
  EXPECT_THAT(ClothingModelFromProto(short_terms),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "clothing basis cb1 is inconsistent"));
  v1::ClothingBasis bad_method = message;
  bad_method.set_method("cubic");
  EXPECT_THAT(ClothingModelFromProto(bad_method),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "unknown clothing method"));
  v1::ClothingBasis bad_corner = message;
  bad_corner.mutable_correspondence()->set_corners(4, 17);
  EXPECT_THAT(BodyCorrespondenceFromProto(bad_corner),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "corner out of range"));
  v1::ClothingBasis nan_mean = message;
  nan_mean.set_mean(0, std::nanf(""));
  EXPECT_THAT(ClothingModelFromProto(nan_mean),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "not finite"));
}

}  // namespace
}  // namespace fitbase::proto
