#include "core/mesh_render.h"

#include <cmath>
#include <vector>

#include "absl/status/status.h"
#include "gtest/gtest.h"

namespace fitbase::core {
namespace {

// An axis-aligned box as 6 outward quads: 8 vertices, meters.
Mesh Box(const Eigen::Vector3d& center, const Eigen::Vector3d& half) {
  Mesh mesh;
  mesh.positions.resize(8, 3);
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d sign((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
    mesh.positions.row(i) = center + sign.cwiseProduct(half);
  }
  mesh.faces.sizes.assign(6, 4);
  mesh.faces.indices = {0, 4, 6, 2, 1, 3, 7, 5, 0, 1, 5, 4, 2, 6, 7, 3, 0, 2, 3, 1, 4, 5, 7, 6};
  return mesh;
}

RenderLayer Layer(Mesh mesh, const Eigen::Vector3d& color) {
  RenderLayer layer;
  layer.mesh = std::move(mesh);
  layer.color = color;
  return layer;
}

int CountLayerPixels(const RenderedImage& image, const ViewFrame& view, int32_t layer) {
  int count = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = view.x0; x < view.x0 + view.width; ++x) count += image.LayerAt(x, y) == layer;
  }
  return count;
}

TEST(MeshRenderTest, NearerCubeShowsInFrontViewAndDepthOrdersTheSideView) {
  const Eigen::Vector3d red(1, 0, 0);
  const Eigen::Vector3d blue(0, 0, 1);
  // The small cube is listed first, so only the z-buffer can put it in front.
  std::vector<RenderLayer> layers = {
      Layer(Box({0, 0, 1.5}, {0.5, 0.5, 0.5}), red),
      Layer(Box({0, 0, 0}, {1, 1, 1}), blue),
  };
  const absl::StatusOr<RenderedImage> image = RenderFrontAndSide(layers, {.height = 200});
  ASSERT_TRUE(image.ok()) << image.status();
  const int cy = image->height / 2;
  const int front_cx = image->front.width / 2;
  EXPECT_EQ(image->LayerAt(front_cx, cy), 0);
  // Facing the camera: full diffuse light, so the colour itself.
  EXPECT_EQ(image->RgbAt(front_cx, cy), Eigen::Vector3i(255, 0, 0));
  const int front_outer = front_cx + static_cast<int>(0.75 * image->pixels_per_meter);
  EXPECT_EQ(image->LayerAt(front_outer, cy), 1);
  EXPECT_EQ(image->RgbAt(front_outer, cy), Eigen::Vector3i(0, 0, 255));

  // Side view, image right = -Z: the front (z = 2) is at the left margin.
  const double margin = std::round(0.05 * image->height);
  const auto side_column = [&](double z) {
    return image->side.x0 + static_cast<int>(margin + (2.0 - z) * image->pixels_per_meter);
  };
  EXPECT_EQ(image->LayerAt(side_column(1.5), cy), 0);
  EXPECT_EQ(image->LayerAt(side_column(0.0), cy), 1);
  const int above_small_cube = cy - static_cast<int>(0.75 * image->pixels_per_meter);
  EXPECT_EQ(image->LayerAt(side_column(1.5), above_small_cube), -1);
  EXPECT_EQ(image->LayerAt(side_column(0.0), above_small_cube), 1);
  EXPECT_EQ(image->LayerAt(image->side.x0 + 1, cy), -1);
}

TEST(MeshRenderTest, EqualDepthGoesToTheLaterLayer) {
  std::vector<RenderLayer> layers = {
      Layer(Box({0, 0, 0}, {1, 1, 1}), {1, 0, 0}),
      Layer(Box({0, 0, 0}, {1, 1, 1}), {0, 1, 0}),
  };
  const absl::StatusOr<RenderedImage> image = RenderFrontAndSide(layers, {.height = 100});
  ASSERT_TRUE(image.ok()) << image.status();
  EXPECT_EQ(CountLayerPixels(*image, image->front, 0), 0);
  EXPECT_GT(CountLayerPixels(*image, image->front, 1), 0);
  EXPECT_EQ(CountLayerPixels(*image, image->side, 0), 0);
}

TEST(MeshRenderTest, TriangleCoverageMatchesProjectedArea) {
  RenderLayer layer;
  layer.mesh.positions.resize(3, 3);
  layer.mesh.positions << 0, 0, 0, 1, 0.1, 0, 0.3, 0.8, 0;
  layer.mesh.faces = {.sizes = {3}, .indices = {0, 1, 2}};
  const absl::StatusOr<RenderedImage> image = RenderFrontAndSide({layer}, {.height = 600});
  ASSERT_TRUE(image.ok()) << image.status();
  const double s = image->pixels_per_meter;
  const double area_px = 0.5 * std::abs(1.0 * 0.8 - 0.1 * 0.3) * s * s;
  const int covered = CountLayerPixels(*image, image->front, 0);
  EXPECT_NEAR(covered, area_px, 0.02 * area_px);
  // Edge-on in the side view: a plane covers no pixel centre there.
  EXPECT_EQ(CountLayerPixels(*image, image->side, 0), 0);
}

TEST(MeshRenderTest, SideViewOfBodyLikeBoxShowsItsDepthAndHeight) {
  // 0.4 m wide, 1.7 m tall, 0.25 m deep, standing on the floor.
  const std::vector<RenderLayer> layers = {
      Layer(Box({0, 0.85, 0}, {0.2, 0.85, 0.125}), {0.8, 0.74, 0.66})};
  const absl::StatusOr<RenderedImage> image = RenderFrontAndSide(layers);
  ASSERT_TRUE(image.ok()) << image.status();
  EXPECT_EQ(image->height, 600);
  const double s = image->pixels_per_meter;
  EXPECT_NEAR(s, (600 - 2 * 30) / 1.7, 1e-9);
  const double side_area = 0.25 * 1.7 * s * s;
  const double front_area = 0.4 * 1.7 * s * s;
  EXPECT_NEAR(CountLayerPixels(*image, image->side, 0), side_area, 0.02 * side_area);
  EXPECT_NEAR(CountLayerPixels(*image, image->front, 0), front_area, 0.02 * front_area);
  EXPECT_NEAR(image->side.width, 0.25 * s + 60, 1.0);
  EXPECT_NEAR(image->front.width, 0.4 * s + 60, 1.0);
  EXPECT_EQ(image->width, image->front.width + image->side.width);
  // The +X face looks straight at the side camera.
  const Eigen::Vector3i centre = image->RgbAt(image->side.x0 + image->side.width / 2, 300);
  EXPECT_EQ(centre, Eigen::Vector3i(204, 189, 168));
}

TEST(MeshRenderTest, ScalarLayerUsesColorScaleAndAddsLegend) {
  RenderLayer layer = Layer(Box({0, 0, 0}, {1, 1, 1}), {0, 0, 0});
  layer.values = Eigen::VectorXd::Constant(8, 0.9);
  layer.value_min = 0.0;
  layer.value_max = 1.0;
  const absl::StatusOr<RenderedImage> image = RenderFrontAndSide({layer}, {.height = 240});
  ASSERT_TRUE(image.ok()) << image.status();
  EXPECT_GT(image->width, image->front.width + image->side.width);
  const Eigen::Vector3d band = ColorScaleColor(0.9, 0.0, 1.0);
  EXPECT_EQ(band, ColorScaleColor(0.99, 0.0, 1.0));
  EXPECT_NE(band, ColorScaleColor(0.1, 0.0, 1.0));
  const Eigen::Vector3i expected = (255 * band).array().round().cast<int>();
  EXPECT_EQ(image->RgbAt(image->front.width / 2, 120), expected);
  // The legend's top box is the highest band, its bottom box the lowest.
  const int legend_cx = image->front.width + image->side.width + 10;
  EXPECT_EQ(image->RgbAt(legend_cx, 20), expected);
  const Eigen::Vector3i lowest = (255 * ColorScaleColor(0.0, 0.0, 1.0)).array().round().cast<int>();
  EXPECT_EQ(image->RgbAt(legend_cx, 240 - 15), lowest);
  EXPECT_EQ(ColorScaleLimits(-2, 6), (std::vector<double>{-2, -1, 0, 1, 2, 3, 4, 5, 6}));
}

TEST(MeshRenderTest, GivenFrameMapsTwoScenesToTheSamePixels) {
  // Alone, the small box would fill the view; framed on the big one, it lands where the big
  // box's render puts the same world points.
  const std::vector<RenderLayer> big = {Layer(Box({0, 0.5, 0}, {0.4, 1, 0.2}), {1, 0, 0})};
  const std::vector<RenderLayer> small = {Layer(Box({0.1, 0.2, 0}, {0.1, 0.1, 0.1}), {0, 0, 1})};
  const Eigen::AlignedBox3d frame(Eigen::Vector3d(-0.4, -0.5, -0.2),
                                  Eigen::Vector3d(0.4, 1.5, 0.2));
  const absl::StatusOr<RenderedImage> a = RenderFrontAndSide(big, {.height = 300, .frame = frame});
  const absl::StatusOr<RenderedImage> b =
      RenderFrontAndSide(small, {.height = 300, .frame = frame});
  ASSERT_TRUE(a.ok()) << a.status();
  ASSERT_TRUE(b.ok()) << b.status();
  EXPECT_EQ(a->width, b->width);
  EXPECT_EQ(a->pixels_per_meter, b->pixels_per_meter);
  EXPECT_EQ(b->pixels_per_meter, (300 - 2 * 15) / 2.0);
  int small_pixels = 0;
  for (int y = 0; y < b->height; ++y) {
    for (int x = 0; x < b->width; ++x) {
      if (b->LayerAt(x, y) != 0) continue;
      ++small_pixels;
      EXPECT_EQ(a->LayerAt(x, y), 0) << x << "," << y;
    }
  }
  const double side_px = 0.2 * b->pixels_per_meter;
  EXPECT_NEAR(small_pixels, 2 * side_px * side_px, 0.1 * side_px * side_px);
}

TEST(MeshRenderTest, RejectsBadLayers) {
  RenderLayer layer = Layer(Box({0, 0, 0}, {1, 1, 1}), {1, 1, 1});
  layer.values = Eigen::VectorXd::Zero(7);
  EXPECT_EQ(RenderFrontAndSide({layer}).status().code(), absl::StatusCode::kInvalidArgument);
  layer.values = Eigen::VectorXd::Zero(8);
  layer.value_max = layer.value_min;
  EXPECT_EQ(RenderFrontAndSide({layer}).status().code(), absl::StatusCode::kInvalidArgument);
  layer.values.resize(0);
  layer.mesh.faces.indices[0] = 8;
  EXPECT_EQ(RenderFrontAndSide({layer}).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(RenderFrontAndSide({}).status().code(), absl::StatusCode::kInvalidArgument);
  layer.mesh.faces.indices[0] = 0;
  const Eigen::AlignedBox3d empty;
  EXPECT_EQ(RenderFrontAndSide({layer}, {.frame = empty}).status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fitbase::core
