#include "core/mesh_render.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "Eigen/Geometry"
#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/status_macros.h"

namespace fitbase::core {
namespace {

// Viridis sampled at the band centres: ordered in lightness, so bands read in greyscale too.
constexpr std::array<std::array<uint8_t, 3>, kColorScaleBands> kBandColors = {{
    {0x44, 0x01, 0x54},
    {0x46, 0x32, 0x7e},
    {0x36, 0x5c, 0x8d},
    {0x27, 0x7f, 0x8e},
    {0x1f, 0xa1, 0x87},
    {0x4a, 0xc1, 0x6d},
    {0xa0, 0xda, 0x39},
    {0xfd, 0xe7, 0x25},
}};

constexpr double kAmbient = 0.3;
constexpr double kDiffuse = 0.7;

// Maps a world point of one view to pixel coordinates (x right, y down) and a depth that grows
// towards the camera.
struct ViewProjection {
  int axis_right;       // world axis along image right.
  double right_sign;    // +1 or -1.
  double right_origin;  // the world coordinate at the view's left margin.
  int axis_depth;       // world axis pointing at the camera.
  double x0;            // pixel column of the view's left edge.
  double margin_px;
  double top;     // the highest world Y.
  double top_px;  // its pixel row.
  double scale;   // pixels per meter.

  Eigen::Vector3d Project(const Eigen::Vector3d& p) const {
    return {x0 + margin_px + right_sign * (p[axis_right] - right_origin) * scale,
            top_px + (top - p[1]) * scale, p[axis_depth]};
  }
};

absl::Status ValidateLayer(const RenderLayer& layer, size_t index) {
  const int64_t vertices = layer.mesh.vertex_count();
  if (!layer.mesh.positions.allFinite()) {
    return absl::InvalidArgumentError(absl::StrCat("layer ", index, ": non-finite position"));
  }
  for (int32_t i : layer.mesh.faces.indices) {
    if (i < 0 || i >= vertices) {
      return absl::InvalidArgumentError(
          absl::StrCat("layer ", index, ": face index ", i, " outside [0, ", vertices, ")"));
    }
  }
  if (layer.values.size() == 0) return absl::OkStatus();
  if (layer.values.size() != vertices) {
    return absl::InvalidArgumentError(absl::StrCat("layer ", index, ": ", layer.values.size(),
                                                   " values for ", vertices, " vertices"));
  }
  if (!layer.values.allFinite()) {
    return absl::InvalidArgumentError(absl::StrCat("layer ", index, ": non-finite value"));
  }
  if (!(layer.value_min < layer.value_max)) {
    return absl::InvalidArgumentError(absl::StrCat(
        "layer ", index, ": value range [", layer.value_min, ", ", layer.value_max, "] is empty"));
  }
  return absl::OkStatus();
}

uint8_t ToByte(double channel) {
  return static_cast<uint8_t>(std::lround(std::clamp(channel, 0.0, 1.0) * 255.0));
}

void SetPixel(RenderedImage& image, int x, int y, const Eigen::Vector3d& color) {
  uint8_t* p = &image.rgb[3 * (static_cast<size_t>(y) * image.width + x)];
  p[0] = ToByte(color[0]);
  p[1] = ToByte(color[1]);
  p[2] = ToByte(color[2]);
}

void DrawLayer(const RenderLayer& layer, int32_t layer_id, const ViewProjection& view,
               const ViewFrame& frame, std::vector<double>& depth, RenderedImage& image) {
  const Triangles triangles = Triangulate(layer.mesh.faces);
  Eigen::Vector3d toward_camera = Eigen::Vector3d::Zero();
  toward_camera[view.axis_depth] = 1.0;
  const bool scalar = layer.values.size() > 0;
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    const Eigen::Vector3d w0 = layer.mesh.positions.row(triangles(t, 0));
    const Eigen::Vector3d w1 = layer.mesh.positions.row(triangles(t, 1));
    const Eigen::Vector3d w2 = layer.mesh.positions.row(triangles(t, 2));
    const Eigen::Vector3d normal = (w1 - w0).cross(w2 - w0);
    const double normal_length = normal.norm();
    if (normal_length == 0.0) continue;
    const double shade = kAmbient + kDiffuse * std::abs(normal.dot(toward_camera)) / normal_length;
    const Eigen::Vector3d p0 = view.Project(w0);
    const Eigen::Vector3d p1 = view.Project(w1);
    const Eigen::Vector3d p2 = view.Project(w2);
    const double area =
        (p1.x() - p0.x()) * (p2.y() - p0.y()) - (p1.y() - p0.y()) * (p2.x() - p0.x());
    if (area == 0.0) continue;  // Edge-on to the camera: covers no pixel centre.
    const int x_begin =
        std::max(frame.x0, static_cast<int>(std::floor(std::min({p0.x(), p1.x(), p2.x()}) - 0.5)));
    const int x_end = std::min(frame.x0 + frame.width - 1,
                               static_cast<int>(std::ceil(std::max({p0.x(), p1.x(), p2.x()}))));
    const int y_begin =
        std::max(0, static_cast<int>(std::floor(std::min({p0.y(), p1.y(), p2.y()}) - 0.5)));
    const int y_end =
        std::min(image.height - 1, static_cast<int>(std::ceil(std::max({p0.y(), p1.y(), p2.y()}))));
    Eigen::Vector3d values = Eigen::Vector3d::Zero();
    if (scalar) {
      values = {layer.values[triangles(t, 0)], layer.values[triangles(t, 1)],
                layer.values[triangles(t, 2)]};
    }
    for (int y = y_begin; y <= y_end; ++y) {
      const double cy = y + 0.5;
      for (int x = x_begin; x <= x_end; ++x) {
        const double cx = x + 0.5;
        // Edge functions divided by the signed area: barycentric weights of either winding.
        const double b0 =
            ((p2.x() - p1.x()) * (cy - p1.y()) - (p2.y() - p1.y()) * (cx - p1.x())) / area;
        const double b1 =
            ((p0.x() - p2.x()) * (cy - p2.y()) - (p0.y() - p2.y()) * (cx - p2.x())) / area;
        const double b2 = 1.0 - b0 - b1;
        if (b0 < 0.0 || b1 < 0.0 || b2 < 0.0) continue;
        const double z = b0 * p0.z() + b1 * p1.z() + b2 * p2.z();
        const size_t pixel = static_cast<size_t>(y) * image.width + x;
        // Only a nearer depth is skipped: at equal depth the later-drawn layer wins.
        if (z < depth[pixel]) continue;
        depth[pixel] = z;
        image.layer_index[pixel] = layer_id;
        const Eigen::Vector3d base =
            scalar ? ColorScaleColor(b0 * values[0] + b1 * values[1] + b2 * values[2],
                                     layer.value_min, layer.value_max)
                   : layer.color;
        SetPixel(image, x, y, shade * base);
      }
    }
  }
}

}  // namespace

std::vector<double> ColorScaleLimits(double min, double max) {
  std::vector<double> limits(kColorScaleBands + 1);
  for (int i = 0; i <= kColorScaleBands; ++i) {
    limits[i] = min + (max - min) * i / kColorScaleBands;
  }
  return limits;
}

Eigen::Vector3d ColorScaleColor(double value, double min, double max) {
  const double t = (value - min) / (max - min);
  const int band =
      std::clamp(static_cast<int>(std::floor(t * kColorScaleBands)), 0, kColorScaleBands - 1);
  const std::array<uint8_t, 3>& c = kBandColors[band];
  return Eigen::Vector3d(c[0], c[1], c[2]) / 255.0;
}

absl::StatusOr<RenderedImage> RenderFrontAndSide(const std::vector<RenderLayer>& layers,
                                                 const RenderOptions& options) {
  if (layers.empty()) return absl::InvalidArgumentError("nothing to render: no layers");
  if (options.height < 16 || options.height > 16384) {
    return absl::InvalidArgumentError(
        absl::StrCat("image height ", options.height, " is outside [16, 16384]"));
  }
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  const RenderLayer* legend = nullptr;
  for (size_t i = 0; i < layers.size(); ++i) {
    RETURN_IF_ERROR(ValidateLayer(layers[i], i));
    const Positions& p = layers[i].mesh.positions;
    if (p.rows() == 0) continue;
    lo = lo.cwiseMin(p.colwise().minCoeff().transpose());
    hi = hi.cwiseMax(p.colwise().maxCoeff().transpose());
    if (legend == nullptr && layers[i].values.size() > 0) legend = &layers[i];
  }
  if (!lo.allFinite()) return absl::InvalidArgumentError("nothing to render: no vertices");
  if (options.frame.has_value()) {
    const Eigen::AlignedBox3d& frame = *options.frame;
    if (!frame.min().allFinite() || !frame.max().allFinite() || frame.isEmpty()) {
      return absl::InvalidArgumentError("render frame is empty or not finite");
    }
    lo = frame.min();
    hi = frame.max();
  }

  const Eigen::Vector3d extent = hi - lo;
  const double margin_px = std::round(options.margin * options.height);
  // The largest extent fits the height, so a wide or deep mesh stays within a sane width too.
  const double span = std::max(extent.maxCoeff(), 1e-9);
  const double scale = (options.height - 2 * margin_px) / span;

  RenderedImage image;
  image.height = options.height;
  image.pixels_per_meter = scale;
  image.front = {0, static_cast<int>(std::ceil(extent.x() * scale + 2 * margin_px))};
  image.side = {image.front.width, static_cast<int>(std::ceil(extent.z() * scale + 2 * margin_px))};
  const int legend_width = legend != nullptr ? std::max(8, options.height / 12) : 0;
  image.width = image.front.width + image.side.width + legend_width;
  const size_t pixels = static_cast<size_t>(image.width) * image.height;
  image.rgb.assign(3 * pixels, 255);
  image.layer_index.assign(pixels, -1);

  // Centred vertically, for meshes wider or deeper than they are tall.
  const double top_px = margin_px + 0.5 * (options.height - 2 * margin_px - extent.y() * scale);
  const ViewProjection front{.axis_right = 0,
                             .right_sign = 1.0,
                             .right_origin = lo.x(),
                             .axis_depth = 2,
                             .x0 = 0.0,
                             .margin_px = margin_px,
                             .top = hi.y(),
                             .top_px = top_px,
                             .scale = scale};
  const ViewProjection side{.axis_right = 2,
                            .right_sign = -1.0,
                            .right_origin = hi.z(),
                            .axis_depth = 0,
                            .x0 = static_cast<double>(image.side.x0),
                            .margin_px = margin_px,
                            .top = hi.y(),
                            .top_px = top_px,
                            .scale = scale};
  image.depth.assign(pixels, -std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < layers.size(); ++i) {
    DrawLayer(layers[i], static_cast<int32_t>(i), front, image.front, image.depth, image);
    DrawLayer(layers[i], static_cast<int32_t>(i), side, image.side, image.depth, image);
  }

  if (legend != nullptr) {
    const int x0 = image.front.width + image.side.width;
    const double band_height = (options.height - 2 * margin_px) / kColorScaleBands;
    const std::vector<double> limits = ColorScaleLimits(legend->value_min, legend->value_max);
    for (int band = 0; band < kColorScaleBands; ++band) {
      // Highest band on top, as values grow upwards on a chart.
      const int y_begin = static_cast<int>(margin_px + (kColorScaleBands - 1 - band) * band_height);
      const int y_end = static_cast<int>(margin_px + (kColorScaleBands - band) * band_height) - 1;
      const Eigen::Vector3d color = ColorScaleColor(0.5 * (limits[band] + limits[band + 1]),
                                                    legend->value_min, legend->value_max);
      for (int y = y_begin; y < y_end; ++y) {
        for (int x = x0 + 2; x < x0 + legend_width - 2; ++x) SetPixel(image, x, y, color);
      }
    }
  }
  return image;
}

}  // namespace fitbase::core
