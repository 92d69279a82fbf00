#include "proto/clothing_basis_codec.h"

#include "core/mesh.h"
#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::proto {
namespace {

clothing::ClothingModel SmallModel() {
  clothing::ClothingModel model;
  model.method = clothing::ClothingMethod::kQuadratic;
  model.component_count = 2;
  model.basis = Eigen::MatrixXf::Random(6, 5);
  model.term_component = {0, 1, 0, 1};
  model.term_power = {1, 1, 2, 2};
  return model;
}

clothing::BodyCorrespondence SmallCorrespondence() {
  clothing::BodyCorrespondence c;
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
  const clothing::ClothingModel original = SmallModel();
  const clothing::BodyCorrespondence original_correspondence = SmallCorrespondence();
  v1::ClothingBasis message;
  ClothingModelToProto(original, &message);
  BodyCorrespondenceToProto(original_correspondence, message.mutable_correspondence());
  EXPECT_EQ(message.method(), "quadratic");
  EXPECT_EQ(message.vertex_count(), 2u);
  const clothing::ClothingModel model = *ClothingModelFromProto(message);
  EXPECT_EQ(model.basis, original.basis);
  EXPECT_EQ(model.term_power, original.term_power);
  const clothing::BodyCorrespondence c = *BodyCorrespondenceFromProto(message);
  EXPECT_EQ(c.corners, original_correspondence.corners);
  EXPECT_EQ(c.barycentric, original_correspondence.barycentric);
  EXPECT_EQ(c.body_components, original_correspondence.body_components);
  EXPECT_EQ(c.body_vertices, original_correspondence.body_vertices);
}

clothing::ClothingModel SmallKernelModel() {
  clothing::ClothingModel model;
  model.method = clothing::ClothingMethod::kKernel;
  model.component_count = 2;
  model.basis = Eigen::MatrixXf::Random(6, 6);  // Mean, 2 linear terms, 3 kernel outputs.
  model.term_component = {0, 1};
  model.term_power = {1, 1};
  model.kernel.length_scale = 0.7f;
  model.kernel.input_scale = Eigen::Vector2f(25, 50);
  model.kernel.centers = Eigen::MatrixXf::Random(2, 4);
  model.kernel.coefficients = Eigen::MatrixXf::Random(3, 4);
  return model;
}

TEST(ClothingBasisCodecTest, RoundTripsAKernelModelAndItsFit) {
  const clothing::ClothingModel original = SmallKernelModel();
  ASSERT_TRUE(clothing::ValidateClothingModel(original).ok());
  v1::ClothingBasis message;
  ClothingModelToProto(original, &message);
  EXPECT_EQ(message.method(), "kernel");
  EXPECT_EQ(message.kernel().output_count(), 3u);
  const absl::StatusOr<clothing::ClothingModel> model = ClothingModelFromProto(message);
  ASSERT_TRUE(model.ok()) << model.status();
  EXPECT_EQ(model->basis, original.basis);
  EXPECT_EQ(model->kernel.shape, core::KernelShape::kGaussian);
  EXPECT_EQ(model->kernel.centers, original.kernel.centers);
  EXPECT_EQ(model->kernel.coefficients, original.kernel.coefficients);
  Eigen::VectorXf features, a, b;
  const Eigen::Vector2f weights(0.01f, -0.02f);
  clothing::FitClothing(original, weights, features, a);
  clothing::FitClothing(*model, weights, features, b);
  EXPECT_EQ(a, b);

  // A Matern kernel keeps its shape; a shape this reader does not know is refused.
  clothing::ClothingModel matern = original;
  matern.kernel.shape = core::KernelShape::kMatern32;
  v1::ClothingBasis matern_message;
  ClothingModelToProto(matern, &matern_message);
  EXPECT_EQ(matern_message.kernel().shape(), v1::KernelCorrection::MATERN_3_2);
  const absl::StatusOr<clothing::ClothingModel> matern_read = ClothingModelFromProto(matern_message);
  ASSERT_TRUE(matern_read.ok()) << matern_read.status();
  EXPECT_EQ(matern_read->kernel.shape, core::KernelShape::kMatern32);
  clothing::FitClothing(matern, weights, features, a);
  clothing::FitClothing(*matern_read, weights, features, b);
  EXPECT_EQ(a, b);
  clothing::FitClothing(original, weights, features, b);
  EXPECT_NE(a, b);
  matern_message.mutable_kernel()->set_shape(static_cast<v1::KernelCorrection::Shape>(7));
  EXPECT_THAT(ClothingModelFromProto(matern_message),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "unknown shape 7"));

  v1::ClothingBasis short_outputs = message;
  short_outputs.mutable_kernel()->mutable_outputs()->RemoveLast();
  EXPECT_THAT(ClothingModelFromProto(short_outputs),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "inconsistent kernel correction"));
  v1::ClothingBasis huge = message;
  huge.mutable_kernel()->set_center_count(1u << 31);
  EXPECT_THAT(ClothingModelFromProto(huge),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "inconsistent kernel correction"));
  v1::ClothingBasis linear_with_kernel = message;
  linear_with_kernel.set_method("linear");
  EXPECT_THAT(ClothingModelFromProto(linear_with_kernel),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "inconsistent kernel correction"));
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

// A 3-vertex garment (one triangle) whose clean-up has a guard, smooths and has the body under
// it (two triangles).
v1::ClothingBasis GuardedBasis() {
  clothing::ClothingModel model;
  model.method = clothing::ClothingMethod::kLinear;
  model.component_count = 2;
  model.basis = Eigen::MatrixXf::Random(9, 3);
  model.term_component = {0, 1};
  model.term_power = {1, 1};
  clothing::BodyCorrespondence c;
  c.offset = 0.0025;
  c.body_vertices = {3, 7, 9, 12};
  c.body_mean = Eigen::VectorXf::Random(12);
  c.body_components = Eigen::MatrixXf::Random(12, 2);
  c.corners.resize(3, 3);
  c.corners << 0, 1, 2, 1, 2, 3, 0, 1, 3;
  c.barycentric = decltype(c.barycentric)::Constant(3, 3, 1.0f / 3);
  c.guard_body = {3};
  c.guard_triangles.resize(1, 3);
  c.guard_triangles << 0, 2, 1;
  c.smoothing_iterations = 4;
  c.body_triangles.resize(2, 3);
  c.body_triangles << 0, 1, 2, 2, 1, 3;
  v1::ClothingBasis message;
  message.set_id("cb2");
  ClothingModelToProto(model, &message);
  BodyCorrespondenceToProto(c, message.mutable_correspondence());
  message.mutable_faces()->set_vertex_count(3);
  message.mutable_faces()->add_face_sizes(3);
  for (uint32_t i : {0u, 1u, 2u}) message.mutable_faces()->add_face_indices(i);
  return message;
}

TEST(ClothingBasisCodecTest, RoundTripsGuardsAndRebuildsTheNeighboursFromTheFaces) {
  const v1::ClothingBasis message = GuardedBasis();
  const absl::StatusOr<clothing::BodyCorrespondence> c = BodyCorrespondenceFromProto(message);
  ASSERT_TRUE(c.ok()) << c.status();
  EXPECT_THAT(c->guard_body, ::testing::ElementsAre(3));
  EXPECT_EQ(c->guard_triangles, Eigen::RowVector3i(0, 2, 1));
  EXPECT_EQ(c->smoothing_iterations, 4);
  EXPECT_EQ(c->body_triangles, (core::Triangles{{0, 1, 2}, {2, 1, 3}}));
  EXPECT_THAT(c->neighbor_offsets, ::testing::ElementsAre(0, 2, 4, 6));
  EXPECT_THAT(c->neighbors, ::testing::ElementsAre(1, 2, 0, 2, 0, 1));
  EXPECT_TRUE(ClothingFitterFromProto(message).ok());
}

// A basis written before guards, smoothing and the body under the garment has none of those
// fields: it loads, and its clean-up pushes vertex by vertex as it did, asking no body.
TEST(ClothingBasisCodecTest, LoadsACorrespondenceWithoutGuards) {
  v1::ClothingBasis message = GuardedBasis();
  message.mutable_correspondence()->clear_guard_body();
  message.mutable_correspondence()->clear_guard_triangles();
  message.mutable_correspondence()->clear_smoothing_iterations();
  message.mutable_correspondence()->clear_body_triangles();
  message.clear_faces();
  const absl::StatusOr<clothing::BodyCorrespondence> c = BodyCorrespondenceFromProto(message);
  ASSERT_TRUE(c.ok()) << c.status();
  EXPECT_TRUE(c->guard_body.empty());
  EXPECT_EQ(c->guard_triangles.rows(), 0);
  EXPECT_EQ(c->smoothing_iterations, 0);
  EXPECT_EQ(c->body_triangles.rows(), 0);
  EXPECT_TRUE(c->neighbor_offsets.empty());
  EXPECT_TRUE(ClothingFitterFromProto(message).ok());
}

TEST(ClothingBasisCodecTest, RejectsBadGuardsAndSmoothing) {
  const v1::ClothingBasis message = GuardedBasis();
  v1::ClothingBasis short_guard = message;
  short_guard.mutable_correspondence()->mutable_guard_triangles()->RemoveLast();
  EXPECT_THAT(BodyCorrespondenceFromProto(short_guard),
              core::StatusIs(absl::StatusCode::kInvalidArgument,
                             "cb2 has an inconsistent body correspondence"));
  v1::ClothingBasis far_guard = message;
  far_guard.mutable_correspondence()->set_guard_body(0, 4);
  EXPECT_THAT(BodyCorrespondenceFromProto(far_guard),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "guard body point 4"));
  v1::ClothingBasis far_corner = message;
  far_corner.mutable_correspondence()->set_guard_triangles(1, 3);
  EXPECT_THAT(BodyCorrespondenceFromProto(far_corner),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "guard triangle corner"));
  v1::ClothingBasis short_region = message;
  short_region.mutable_correspondence()->mutable_body_triangles()->RemoveLast();
  EXPECT_THAT(BodyCorrespondenceFromProto(short_region),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "inconsistent"));
  v1::ClothingBasis far_region = message;
  far_region.mutable_correspondence()->set_body_triangles(4, 4);
  EXPECT_THAT(BodyCorrespondenceFromProto(far_region),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "body triangle corner outside"));
  v1::ClothingBasis too_smooth = message;
  too_smooth.mutable_correspondence()->set_smoothing_iterations(1u << 31);
  EXPECT_THAT(BodyCorrespondenceFromProto(too_smooth),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "inconsistent"));
  v1::ClothingBasis no_faces = message;
  no_faces.clear_faces();
  EXPECT_THAT(BodyCorrespondenceFromProto(no_faces),
              core::StatusIs(absl::StatusCode::kInvalidArgument, "has faces for 0 vertices"));
  v1::ClothingBasis bad_face = message;
  bad_face.mutable_faces()->set_face_indices(2, 7);
  EXPECT_EQ(BodyCorrespondenceFromProto(bad_face).status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fitbase::proto
