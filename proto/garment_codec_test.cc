#include "proto/garment_codec.h"

#include "core/test_support.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "proto/mesh_codec.h"

namespace fitbase::proto {
namespace {

using core::StatusIs;

core::MhcloBinding SampleBinding() {
  core::MhcloBinding b;
  b.reference_vertices.resize(2, 3);
  b.reference_vertices << 0, 1, 2, 3, 3, 3;
  b.weights.resize(2, 3);
  b.weights << 0.5, 0.25, 0.25, 1, 0, 0;
  b.offsets.resize(2, 3);
  b.offsets << 0.1, -0.2, 0.3, 0, 0, 0;
  b.scales = {{{0, 1, 1.5}, {2, 3, 2.5}, {1, 2, 1.25}}};
  return b;
}

TEST(GarmentCodecTest, BindingRoundTrip) {
  auto back = MhcloBindingFromProto(MhcloBindingToProto(SampleBinding()), 2, 4);
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(back->reference_vertices, SampleBinding().reference_vertices);
  EXPECT_EQ(back->weights, SampleBinding().weights);
  EXPECT_EQ(back->offsets, SampleBinding().offsets);
  EXPECT_EQ(back->scales[1].j, 3);
  EXPECT_EQ(back->scales[2].reference_distance, 1.25);
}

TEST(GarmentCodecTest, BindingIsValidated) {
  const v1::MhcloBinding good = MhcloBindingToProto(SampleBinding());
  EXPECT_THAT(MhcloBindingFromProto(good, 3, 4),
              StatusIs(absl::StatusCode::kInvalidArgument, "binding has 2 vertices; the garment has 3"));
  EXPECT_THAT(MhcloBindingFromProto(good, 2, 3),
              StatusIs(absl::StatusCode::kInvalidArgument, "beyond the reference mesh's 3"));
  v1::MhcloBinding nan = good;
  nan.set_offsets(1, std::nan(""));
  EXPECT_THAT(MhcloBindingFromProto(nan, 2, 4),
              StatusIs(absl::StatusCode::kInvalidArgument, "non-finite"));
  v1::MhcloBinding no_scale = good;
  no_scale.clear_scale_reference_distances();
  EXPECT_THAT(MhcloBindingFromProto(no_scale, 2, 4),
              StatusIs(absl::StatusCode::kInvalidArgument, "x, y and z scales"));
}

v1::Garment SampleGarment() {
  core::Mesh mesh;
  mesh.positions = core::Positions::Random(4, 3);
  mesh.faces.sizes = {4};
  mesh.faces.indices = {0, 1, 2, 3};
  v1::Garment g;
  *g.mutable_template_mesh() = MeshToProto(mesh);
  for (float t : {0.f, 0.f, 1.f, 0.f, 1.f, 1.f}) g.add_texcoords(t);
  for (int t : {0, 1, 2, -1}) g.add_face_texcoord_indices(t);
  for (int v = 0; v < 4; ++v) {
    for (float a : {0.f, 1.f, 0.f}) g.add_length_axes(a);
    g.add_vertex_regions(v % 4);
  }
  return g;
}

TEST(GarmentCodecTest, TemplateAxesAndRegions) {
  const v1::Garment g = SampleGarment();
  auto mesh = GarmentTemplateFromProto(g);
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  EXPECT_EQ(mesh->texcoords.rows(), 3);
  EXPECT_EQ(mesh->face_texcoord_indices, (std::vector<int32_t>{0, 1, 2, -1}));
  auto axes = LengthAxesFromProto(g);
  ASSERT_TRUE(axes.ok());
  EXPECT_EQ(axes->col(1).sum(), 4.0);
  auto regions = RegionsFromProto(g);
  ASSERT_TRUE(regions.ok());
  EXPECT_EQ((*regions)[3], body::BodyRegion::kFeet);
}

TEST(GarmentCodecTest, InconsistentGarmentsAreRejected) {
  v1::Garment g = SampleGarment();
  g.set_face_texcoord_indices(1, 7);
  EXPECT_THAT(GarmentTemplateFromProto(g),
              StatusIs(absl::StatusCode::kInvalidArgument, "texture index 7"));
  g = SampleGarment();
  g.add_length_axes(1.f);
  EXPECT_THAT(LengthAxesFromProto(g), StatusIs(absl::StatusCode::kInvalidArgument, "length axes"));
  g = SampleGarment();
  g.set_vertex_regions(0, 9);
  EXPECT_THAT(RegionsFromProto(g), StatusIs(absl::StatusCode::kInvalidArgument, "region 9"));
}

}  // namespace
}  // namespace fitbase::proto
