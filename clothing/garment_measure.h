#ifndef FITBASE_CLOTHING_GARMENT_MEASURE_H_
#define FITBASE_CLOTHING_GARMENT_MEASURE_H_

#include <functional>
#include <optional>
#include <span>

#include "Eigen/Core"
#include "body/body_measurements.h"
#include "core/mesh.h"
#include "core/triangle_bvh.h"

namespace fitbase::clothing {

// A garment size's rest edge lengths by triangle: row t holds the rest lengths of the edges
// (corner 0, corner 1), (1, 2) and (2, 0) of triangle t, m. T x 3.
using TriangleEdgeLengths = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

// A garment's girth where a body girth was taken.
struct GarmentGirth {
  double fitted = 0;   // Convex hull perimeter of the fitted garment's loop (a tape over it), m.
  double rest = 0;     // Length of the same material loop in the size's rest shape, m.
  double stretch = 0;  // The loop's fitted length over its rest length, minus 1.
  // Where a loop bridges a gap (left by `counts`), the bridge takes the material's stretch.
};

// The garment's girth in the plane of `place` (a body girth place, MeasureBody): of the
// fitted garment's closed loops in that plane that enclose place.inside and none of
// `outside` (the other leg's centre, for a thigh), the innermost (the layer that holds the
// body there: a waistband inside a hanging top). Chains that meet at a seam (ends within
// 1 cm) count as one loop. With `counts`, only the section's points it accepts count (a
// chest's loop leaves the sleeves beside it); the gaps this opens are bridged straight, as a
// tape bridges them. nullopt when no loop qualifies: the garment does not go round the body
// there. fitted: V x 3 (m); triangles: T x 3; rest: T x 3 (m), all of one garment.
std::optional<GarmentGirth> GarmentGirthAt(
    const core::Positions& fitted, const core::Triangles& triangles,
    const TriangleEdgeLengths& rest, const body::GirthPlace& place,
    std::span<const Eigen::Vector3d> outside = {},
    const std::function<bool(const Eigen::Vector3d&)>& counts = nullptr);

// Per vertex, the mean over its edges of l / l0 - 1, in %: positive stretched, negative
// gathered. V (0 for a vertex on no triangle).
Eigen::VectorXf VertexStretchPercent(const core::Positions& fitted,
                                     const core::Triangles& triangles,
                                     const TriangleEdgeLengths& rest);

// Per vertex, its signed distance to the body surface in mm (negative inside the body),
// clamped to +-max_mm where nothing of the body lies closer. V.
Eigen::VectorXf VertexEaseMm(const core::Positions& fitted, const core::TriangleBvh& body,
                             double max_mm);

}  // namespace fitbase::clothing

#endif  // FITBASE_CLOTHING_GARMENT_MEASURE_H_
