#ifndef FITBASE_CORE_MESH_RENDER_H_
#define FITBASE_CORE_MESH_RENDER_H_

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "Eigen/Core"
#include "Eigen/Geometry"
#include "absl/status/statusor.h"
#include "core/mesh.h"

namespace fitbase::core {

// One mesh to draw: a flat colour, or per-vertex scalars through the colour scale.
struct RenderLayer {
  Mesh mesh;                             // positions V x 3, meters, +Y up, +Z front.
  Eigen::Vector3d color{0.8, 0.8, 0.8};  // RGB in [0, 1]; used when `values` is empty.
  Eigen::VectorXd values;                // empty, or V scalars in any unit.
  double value_min = 0.0;                // `values` at or below: the first band.
  double value_max = 1.0;                // `values` at or above: the last band.
};

struct RenderOptions {
  int height = 600;      // pixels; the width follows from the meshes' extent.
  double margin = 0.05;  // of the height, around each view.
  // The world box (m) the views frame; empty: the union bounding box of all layers. Two renders
  // with the same frame and height map every world point to the same pixel, so they compare
  // pixel by pixel; what lies outside the frame is clipped at the views' edges.
  std::optional<Eigen::AlignedBox3d> frame;
};

// A view's place in the image: columns [x0, x0 + width).
struct ViewFrame {
  int x0 = 0;
  int width = 0;
};

struct RenderedImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgb;          // height x width x 3, rows from the top.
  std::vector<int32_t> layer_index;  // height x width: the visible layer, or -1 for none.
  // height x width: the visible surface's world coordinate along the axis towards the camera
  // (m; +Z in the front view, +X in the side view), -infinity for none.
  std::vector<double> depth;
  ViewFrame front;                   // camera at +Z looking along -Z, image right = +X.
  ViewFrame side;                    // camera at +X looking along -X, image right = -Z.
  double pixels_per_meter = 0.0;     // the same in both views.

  int32_t LayerAt(int x, int y) const { return layer_index[y * width + x]; }
  Eigen::Vector3i RgbAt(int x, int y) const {
    const uint8_t* p = &rgb[3 * (y * width + x)];
    return {p[0], p[1], p[2]};
  }
};

// The colour scale has this many bands, so a legend can show each one exactly.
inline constexpr int kColorScaleBands = 8;

// The kColorScaleBands + 1 band limits from `min` to `max`, ascending (same unit).
std::vector<double> ColorScaleLimits(double min, double max);

// RGB in [0, 1] of the band holding `value` (clamped to [min, max]; min < max).
Eigen::Vector3d ColorScaleColor(double value, double min, double max);

// Orthographic front and side views side by side, framed on options.frame (by default the union
// bounding box of all layers), z-buffered, flat Lambert shading lit from the camera (two-sided:
// ambient 0.3 plus 0.7 |n . view|) on a white background. Pixels are sampled at their centres;
// at equal depth the later layer wins, so a garment listed after its body shows where they
// touch. If any layer has values, a legend strip of the colour scale's bands (highest on top,
// first such layer's range) is drawn right of the views. Errors (INVALID_ARGUMENT): no layers,
// no vertices at all, a height outside [16, 16384], values not one per vertex or non-finite,
// value_min >= value_max, a face index out of range, a frame that is empty or not finite.
absl::StatusOr<RenderedImage> RenderFrontAndSide(const std::vector<RenderLayer>& layers,
                                                 const RenderOptions& options = {});

}  // namespace fitbase::core

#endif  // FITBASE_CORE_MESH_RENDER_H_
