#include "pipeline/skin_visibility.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "absl/status/status.h"
#include "core/mesh_render.h"
#include "gtest/gtest.h"

namespace fitbase::pipeline {
namespace {

// A body-like box 0.4 m wide, 1 m tall, 0.2 m deep: 8 corners, 12 outward triangles.
struct Box {
  core::Positions positions;
  core::Triangles triangles;
};

Box BodyBox() {
  Box box;
  box.positions.resize(8, 3);
  for (int i = 0; i < 8; ++i) {
    box.positions.row(i) << ((i & 1) ? 0.2 : -0.2), ((i & 2) ? 1.5 : 0.5), ((i & 4) ? 0.1 : -0.1);
  }
  box.triangles.resize(12, 3);
  box.triangles << 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 2, 3,
      0, 3, 1, 4, 5, 7, 4, 7, 6;
  return box;
}

// A 0.2 m square patch before the box's front face, as two unconnected halves (left x < 0,
// right x > 0) at depths z_left and z_right.
core::Positions Patch(double z_left, double z_right) {
  core::Positions p(8, 3);
  p << -0.1, 0.9, z_left, 0.0, 0.9, z_left, 0.0, 1.1, z_left, -0.1, 1.1, z_left,  //
      0.0, 0.9, z_right, 0.1, 0.9, z_right, 0.1, 1.1, z_right, 0.0, 1.1, z_right;
  return p;
}

core::Triangles PatchTriangles() {
  core::Triangles t(4, 3);
  t << 0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7;
  return t;
}

TEST(SkinVisibilityTest, ADrapeAgainstItselfShowsNoSkin) {
  const Box body = BodyBox();
  const core::Positions garment = Patch(0.11, 0.11);
  const core::Triangles triangles = PatchTriangles();
  const DressedBody drape{&body.positions, &body.triangles, &garment, &triangles};
  const absl::StatusOr<SkinVisibility> skin = MeasureVisibleSkin(drape, drape);
  ASSERT_TRUE(skin.ok()) << skin.status();
  EXPECT_GT(skin->cloth_pixels, 1000);
  EXPECT_EQ(skin->skin_pixels, 0);
  EXPECT_EQ(skin->share(), 0.0);
}

TEST(SkinVisibilityTest, CountsTheClothThatSinksUnderTheSkin) {
  const Box body = BodyBox();
  const core::Positions draped = Patch(0.11, 0.11);
  // The right half 1 cm inside the body: the front view shows skin there. The patch is edge-on
  // in the side view, so only the front view counts.
  const core::Positions fitted = Patch(0.11, 0.09);
  const core::Triangles triangles = PatchTriangles();
  const DressedBody drape{&body.positions, &body.triangles, &draped, &triangles};
  const DressedBody fit{&body.positions, &body.triangles, &fitted, &triangles};
  const absl::StatusOr<SkinVisibility> skin = MeasureVisibleSkin(drape, fit);
  ASSERT_TRUE(skin.ok()) << skin.status();
  EXPECT_NEAR(skin->share(), 0.5, 0.02);
  // The frame is the union of both scenes: 1.0 m tall, at 600 - 2 x 30 px.
  const double side_px = 0.2 * (600 - 60) / 1.0;
  EXPECT_NEAR(skin->cloth_pixels, side_px * side_px, 0.03 * side_px * side_px);
  // The sunk half's outer border, kClothEdgeBand wide, lies along the drape's edge; the rest of
  // it is the body through the cloth.
  const double band_px = std::ceil(kClothEdgeBand * (600 - 60) / 1.0);
  EXPECT_NEAR(skin->inside_share(), (0.5 - band_px / side_px) * (1 - 2 * band_px / side_px),
              0.02);
  // Against the fit as reference, the sunk half shows no cloth at all.
  const absl::StatusOr<SkinVisibility> reverse = MeasureVisibleSkin(fit, drape);
  ASSERT_TRUE(reverse.ok()) << reverse.status();
  EXPECT_EQ(reverse->skin_pixels, 0);
  EXPECT_NEAR(reverse->cloth_pixels, 0.5 * skin->cloth_pixels, 0.03 * skin->cloth_pixels);
}

TEST(SkinVisibilityTest, AHemAFewMillimetresHigherIsAnEdgeNotSkinThroughTheCloth) {
  const Box body = BodyBox();
  const core::Positions draped = Patch(0.11, 0.11);
  core::Positions raised = draped;
  raised.col(1).array() += 0.006;
  const core::Triangles triangles = PatchTriangles();
  const absl::StatusOr<SkinVisibility> skin =
      MeasureVisibleSkin({&body.positions, &body.triangles, &draped, &triangles},
                         {&body.positions, &body.triangles, &raised, &triangles});
  ASSERT_TRUE(skin.ok()) << skin.status();
  // The lowest 6 mm of the drape's cloth shows skin in the front view: 0.006 / 0.2 of it.
  EXPECT_NEAR(skin->share(), 0.03, 0.01);
  EXPECT_EQ(skin->edge_skin_pixels, skin->skin_pixels);
  EXPECT_EQ(skin->inside_share(), 0.0);
}

TEST(SkinVisibilityTest, ThePictureMarksTheSkinWhereItShows) {
  const Box body = BodyBox();
  const core::Positions draped = Patch(0.11, 0.11);
  const core::Positions fitted = Patch(0.11, 0.09);
  const core::Triangles triangles = PatchTriangles();
  SkinPicture picture;
  const absl::StatusOr<SkinVisibility> skin =
      MeasureVisibleSkin({&body.positions, &body.triangles, &draped, &triangles},
                         {&body.positions, &body.triangles, &fitted, &triangles},
                         kSkinViewHeight, &picture);
  ASSERT_TRUE(skin.ok()) << skin.status();
  ASSERT_EQ(picture.height, kSkinViewHeight);
  ASSERT_EQ(picture.pixels.size(), static_cast<size_t>(picture.width) * picture.height);
  int64_t edge = 0;
  int64_t inside = 0;
  double inside_x = 0;
  for (int y = 0; y < picture.height; ++y) {
    for (int x = 0; x < picture.width; ++x) {
      const SkinPixel pixel = picture.pixels[y * picture.width + x];
      edge += pixel == SkinPixel::kEdge;
      if (pixel == SkinPixel::kInside) {
        ++inside;
        inside_x += x;
      }
    }
  }
  EXPECT_EQ(edge, skin->edge_skin_pixels);
  EXPECT_EQ(edge + inside, skin->skin_pixels);
  // The sunk half is the right one (+X), which the front view draws right of the box's middle.
  const core::RenderOptions options{.height = kSkinViewHeight, .frame = picture.frame};
  std::vector<core::RenderLayer> layers(1);
  layers[0].mesh.positions = body.positions;
  layers[0].mesh.faces.sizes.assign(12, 3);
  layers[0].mesh.faces.indices.assign(body.triangles.data(),
                                      body.triangles.data() + body.triangles.size());
  const absl::StatusOr<core::RenderedImage> image = core::RenderFrontAndSide(layers, options);
  ASSERT_TRUE(image.ok()) << image.status();
  EXPECT_EQ(image->width, picture.width);
  ASSERT_GT(inside, 0);
  EXPECT_GT(inside_x / inside, image->front.x0 + 0.5 * image->front.width);
  EXPECT_LT(inside_x / inside, image->front.x0 + image->front.width);
}

TEST(SkinVisibilityTest, EdgesRaisedLieBackAtTheBottomAndOutAtTheTop) {
  // One 0.2 m square of 2 x 2 quads (9 vertices, row-major from the bottom left), 8 triangles.
  core::Positions square(9, 3);
  for (int v = 0; v < 9; ++v) square.row(v) << -0.1 + 0.1 * (v % 3), 0.9 + 0.1 * (v / 3), 0.11;
  core::Triangles triangles(8, 3);
  for (int q = 0; q < 4; ++q) {
    const int v = q % 2 + 3 * (q / 2);
    triangles.row(2 * q) << v, v + 1, v + 4;
    triangles.row(2 * q + 1) << v, v + 4, v + 3;
  }
  const GarmentEdges edges = FindGarmentEdges(triangles);
  EXPECT_EQ(edges.vertices, (std::vector<int32_t>{0, 1, 2, 3, 5, 6, 7, 8}));
  // Vertex 1, the middle of the bottom edge: 0 and 2 along the edge, 4 and 5 into the cloth.
  std::vector<int32_t> bottom_middle = edges.neighbours[1];
  std::sort(bottom_middle.begin(), bottom_middle.end());
  EXPECT_EQ(bottom_middle, (std::vector<int32_t>{0, 2, 4, 5}));
  std::vector<int32_t> bottom_middle_along = edges.along[1];
  std::sort(bottom_middle_along.begin(), bottom_middle_along.end());
  EXPECT_EQ(bottom_middle_along, (std::vector<int32_t>{0, 2}));
  core::Positions raised = square;
  raised.col(1).array() += 0.006;
  const Eigen::VectorXd retreat = EdgeRetreat(edges, square, raised);
  ASSERT_EQ(retreat.size(), 8);
  // The middles of the bottom and top edges move straight into and out of the cloth; the sides'
  // middles along their edge, neither.
  EXPECT_NEAR(retreat[1], 0.006, 1e-9);
  EXPECT_NEAR(retreat[6], -0.006, 1e-9);
  EXPECT_NEAR(retreat[3], 0.0, 1e-9);
  EXPECT_NEAR(retreat[4], 0.0, 1e-9);
  // Shrunk about its middle, every edge lies back.
  core::Positions shrunk = square;
  const Eigen::RowVector3d middle = square.row(4);
  for (int v = 0; v < 9; ++v) shrunk.row(v) = middle + 0.9 * (square.row(v) - middle);
  const Eigen::VectorXd shrunk_retreat = EdgeRetreat(edges, square, shrunk);
  EXPECT_GT(shrunk_retreat.minCoeff(), 0.0);
}

// The box and, 5 cm before the patch's left half, a 0.1 m cube standing for a forearm.
Box BodyAndLimb() {
  Box scene = BodyBox();
  Box limb = BodyBox();
  for (Eigen::Index v = 0; v < 8; ++v) {
    limb.positions.row(v) << ((v & 1) ? 0.0 : -0.1), ((v & 2) ? 1.05 : 0.95), ((v & 4) ? 0.26 : 0.16);
  }
  scene.positions.conservativeResize(16, 3);
  scene.positions.bottomRows(8) = limb.positions;
  scene.triangles.conservativeResize(24, 3);
  scene.triangles.bottomRows(12) = limb.triangles.array() + 8;
  return scene;
}

TEST(SkinVisibilityTest, ADrapeOutsideItsBodyShowsNoSkinThroughItsCloth) {
  const Box body = BodyAndLimb();
  const core::Positions garment = Patch(0.11, 0.11);
  const core::Triangles triangles = PatchTriangles();
  const absl::StatusOr<SkinVisibility> skin =
      MeasureSkinThroughCloth({&body.positions, &body.triangles, &garment, &triangles});
  ASSERT_TRUE(skin.ok()) << skin.status();
  // The limb hides a quarter of the patch (half its width, half its height), which counts as
  // neither cloth nor skin.
  const double side_px = 0.2 * (600 - 60) / 1.0;
  EXPECT_NEAR(skin->cloth_pixels, 0.75 * side_px * side_px, 0.03 * side_px * side_px);
  EXPECT_EQ(skin->skin_pixels, 0);
}

TEST(SkinVisibilityTest, CountsTheSkinThatPokesThroughADrapesOwnCloth) {
  const Box body = BodyAndLimb();
  // The right half 1 cm inside the body: the body shows through it in the front view.
  const core::Positions garment = Patch(0.11, 0.09);
  const core::Triangles triangles = PatchTriangles();
  const absl::StatusOr<SkinVisibility> skin =
      MeasureSkinThroughCloth({&body.positions, &body.triangles, &garment, &triangles});
  ASSERT_TRUE(skin.ok()) << skin.status();
  EXPECT_NEAR(skin->share(), 0.5 / 0.75, 0.03);
  // Sunk 3 cm, beyond kClothCoverDepth, the half is taken for cloth hidden by the body.
  const core::Positions deep = Patch(0.11, 0.07);
  const absl::StatusOr<SkinVisibility> hidden =
      MeasureSkinThroughCloth({&body.positions, &body.triangles, &deep, &triangles});
  ASSERT_TRUE(hidden.ok()) << hidden.status();
  EXPECT_EQ(hidden->skin_pixels, 0);
}

TEST(SkinVisibilityTest, RejectsMissingEmptyOrBrokenMeshes) {
  const Box body = BodyBox();
  const core::Positions garment = Patch(0.11, 0.11);
  core::Triangles triangles = PatchTriangles();
  const DressedBody good{&body.positions, &body.triangles, &garment, &triangles};
  DressedBody missing = good;
  missing.garment = nullptr;
  EXPECT_EQ(MeasureVisibleSkin(good, missing).status().code(),
            absl::StatusCode::kInvalidArgument);
  const core::Positions empty;
  DressedBody hollow = good;
  hollow.garment = &empty;
  EXPECT_EQ(MeasureVisibleSkin(hollow, good).status().code(), absl::StatusCode::kInvalidArgument);
  core::Positions nan = garment;
  nan(0, 0) = std::nan("");
  DressedBody broken = good;
  broken.garment = &nan;
  EXPECT_EQ(MeasureVisibleSkin(good, broken).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(MeasureVisibleSkin(good, good, 8).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(MeasureSkinThroughCloth(missing).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(MeasureSkinThroughCloth(broken).status().code(), absl::StatusCode::kInvalidArgument);
  triangles(0, 0) = 8;
  EXPECT_EQ(MeasureVisibleSkin(good, good).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(MeasureSkinThroughCloth(good).status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fitbase::pipeline
