#include "proto/avatar_basis_codec.h"

#include <cmath>
#include <limits>
#include <string>

#include "absl/status/status.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::proto {
namespace {

using ::testing::HasSubstr;

constexpr char kTopology[] = "test-quad-pair";

// D = 3 * 4 with 2 orthonormal components (variance descending), built by hand.
core::PcaBasis SampleBasis() {
  core::PcaBasis basis;
  basis.mean.resize(12);
  basis.mean << 0.1, 0.2, 0.3, 1.1, 0.2, 0.3, 1.1, 1.7, 0.3, 0.1, 1.7, -0.45;
  basis.components = Eigen::MatrixXd::Zero(12, 2);
  // Column 0: (1, 1, 1, 1) / 2 on the x coordinates. Column 1: (1, -1) / sqrt(2) on y0, z3.
  for (int v = 0; v < 4; ++v) basis.components(3 * v, 0) = 0.5;
  basis.components(1, 1) = 1.0 / std::sqrt(2.0);
  basis.components(11, 1) = -1.0 / std::sqrt(2.0);
  basis.variances.resize(2);
  basis.variances << 4e-4, 1e-5;
  basis.total_variance = 4.2e-4;
  basis.explained_variance_ratio = basis.variances / basis.total_variance;
  basis.training_error = {.mean_mm = 0.75, .max_mm = 3.5};
  basis.sample_count = 5;
  return basis;
}

core::PolygonFaces SampleFaces() {
  core::PolygonFaces faces;
  faces.sizes = {3, 3};
  faces.indices = {0, 1, 2, 0, 2, 3};
  return faces;
}

v1::AvatarBasis SampleMessage() {
  return AvatarBasisToProto(SampleBasis(), kTopology, SampleFaces());
}

void ExpectInvalid(const v1::AvatarBasis& message, const std::string& needle) {
  EXPECT_THAT(PcaBasisFromProto(message), core::StatusIs(absl::StatusCode::kInvalidArgument, needle));
}

TEST(AvatarBasisCodecTest, SampleBasisIsOrthonormal) {
  const core::PcaBasis basis = SampleBasis();
  EXPECT_TRUE((basis.components.transpose() * basis.components)
                  .isApprox(Eigen::Matrix2d::Identity(), 1e-15));
}

TEST(AvatarBasisCodecTest, ToProtoLaysOutComponentsComponentMajor) {
  const v1::AvatarBasis message = SampleMessage();
  EXPECT_EQ(message.topology_id(), kTopology);
  EXPECT_EQ(message.component_count(), 2u);
  ASSERT_EQ(message.components_size(), 24);
  EXPECT_EQ(message.components(0), 0.5f);    // Component 0, x0.
  EXPECT_EQ(message.components(1), 0.0f);    // Component 0, y0.
  EXPECT_EQ(message.components(12), 0.0f);   // Component 1, x0.
  EXPECT_EQ(message.components(13), static_cast<float>(1.0 / std::sqrt(2.0)));  // y0.
  EXPECT_EQ(message.components(23), static_cast<float>(-1.0 / std::sqrt(2.0)));  // z3.
  ASSERT_EQ(message.variances_size(), 2);
  EXPECT_EQ(message.variances(0), 4e-4);
  EXPECT_EQ(message.variances(1), 1e-5);
  ASSERT_EQ(message.explained_variance_ratio_size(), 2);
  EXPECT_EQ(message.total_variance(), 4.2e-4);
  EXPECT_EQ(message.training_mean_error_mm(), 0.75);
  EXPECT_EQ(message.training_max_error_mm(), 3.5);
}

TEST(AvatarBasisCodecTest, MeanMeshCarriesFacesAndTopologyId) {
  const v1::AvatarBasis message = SampleMessage();
  const v1::Mesh& mean = message.mean();
  EXPECT_EQ(mean.topology_id(), kTopology);
  EXPECT_EQ(mean.vertex_count(), 4u);
  ASSERT_EQ(mean.positions_size(), 12);
  EXPECT_EQ(mean.positions(4), 0.2f);    // y1.
  EXPECT_EQ(mean.positions(11), -0.45f);  // z3.
  EXPECT_THAT(mean.face_sizes(), ::testing::ElementsAre(3u, 3u));
  EXPECT_THAT(mean.face_indices(), ::testing::ElementsAre(0u, 1u, 2u, 0u, 2u, 3u));
}

TEST(AvatarBasisCodecTest, RoundTripKeepsBasisWithinFloat32Precision) {
  const core::PcaBasis original = SampleBasis();
  v1::AvatarBasis message = SampleMessage();
  message.mutable_population()->set_count(5);
  auto decoded = PcaBasisFromProto(message);
  ASSERT_TRUE(decoded.ok()) << decoded.status();
  ASSERT_EQ(decoded->mean.size(), 12);
  for (int i = 0; i < 12; ++i) {
    EXPECT_NEAR(decoded->mean(i), original.mean(i), 1e-6 * std::abs(original.mean(i))) << i;
  }
  ASSERT_EQ(decoded->components.rows(), 12);
  ASSERT_EQ(decoded->components.cols(), 2);
  EXPECT_TRUE(decoded->components.isApprox(original.components, 1e-7));
  EXPECT_EQ(decoded->components(11, 0), 0.0);  // Zeros stay exact.
  // The doubles are stored as doubles.
  EXPECT_EQ(decoded->variances, original.variances);
  EXPECT_EQ(decoded->explained_variance_ratio, original.explained_variance_ratio);
  EXPECT_EQ(decoded->total_variance, original.total_variance);
  EXPECT_EQ(decoded->training_error.mean_mm, 0.75);
  EXPECT_EQ(decoded->training_error.max_mm, 3.5);
  EXPECT_EQ(decoded->sample_count, 5);
}

TEST(AvatarBasisCodecTest, MissingComponentValueIsInconsistent) {
  v1::AvatarBasis message = SampleMessage();
  message.mutable_components()->RemoveLast();
  ExpectInvalid(message, "inconsistent");
  ExpectInvalid(message, "found 23 values");
}

TEST(AvatarBasisCodecTest, ComponentCountNotMatchingValuesIsInconsistent) {
  v1::AvatarBasis message = SampleMessage();
  message.set_component_count(3);
  ExpectInvalid(message, "3 components of size 12 need 36 values");
}

TEST(AvatarBasisCodecTest, MissingVarianceIsInconsistent) {
  v1::AvatarBasis message = SampleMessage();
  message.mutable_variances()->RemoveLast();
  ExpectInvalid(message, "1 variances");
}

TEST(AvatarBasisCodecTest, MissingExplainedVarianceRatioIsInconsistent) {
  v1::AvatarBasis message = SampleMessage();
  message.add_explained_variance_ratio(0.0);
  ExpectInvalid(message, "3 explained-variance ratios");
}

TEST(AvatarBasisCodecTest, NonPositiveVarianceIsRejected) {
  v1::AvatarBasis message = SampleMessage();
  message.set_variances(1, 0.0);
  ExpectInvalid(message, "non-positive");
  message.set_variances(1, -1e-5);
  ExpectInvalid(message, "non-positive");
  message.set_variances(1, std::numeric_limits<double>::quiet_NaN());
  ExpectInvalid(message, "non-finite variance");
}

TEST(AvatarBasisCodecTest, NonFiniteComponentIsRejected) {
  v1::AvatarBasis message = SampleMessage();
  message.set_components(5, std::numeric_limits<float>::infinity());
  ExpectInvalid(message, "non-finite components");
}

TEST(AvatarBasisCodecTest, EmptyBasisIsRejected) {
  v1::AvatarBasis message = SampleMessage();
  message.set_component_count(0);
  message.clear_components();
  message.clear_variances();
  message.clear_explained_variance_ratio();
  ExpectInvalid(message, "empty");

  ExpectInvalid(v1::AvatarBasis(), "empty");
}

TEST(AvatarBasisCodecTest, InvalidMeanMeshIsRejected) {
  v1::AvatarBasis message = SampleMessage();
  message.mutable_mean()->set_face_indices(5, 4);  // vertex_count is 4.
  ExpectInvalid(message, "face index 4");
}

}  // namespace
}  // namespace fitbase::proto
