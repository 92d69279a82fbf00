#ifndef FITBASE_WORKERS_FIT_METRICS_H_
#define FITBASE_WORKERS_FIT_METRICS_H_

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "Eigen/Core"
#include "body/body_skeleton.h"
#include "core/mesh.h"
#include "core/triangle_bvh.h"
#include "workers/cloth_model.h"

namespace fitbase::workers {

// A drape whose p99 edge stretch exceeds this is flagged: the size is too small for the body
// (a single edge over it is a local defect, reported as strain_max, not a verdict on the size).
// Compression is no verdict on the size: it is cloth gathered where a garment is too long or
// too wide for the body.
inline constexpr double kOverstretchStrain = 0.15;
// A garment vertex nearer the body than this (m) counts as penetrating in the strict measure.
inline constexpr double kPenetrationDistance = 0.001;

struct RegionEase {
  body::BodyRegion region;
  int64_t vertex_count = 0;
  double mean_mm = 0;
  double p95_mm = 0;
};

// How a garment sits on a body. Distances in mm, strain as a ratio.
struct FitMetrics {
  int64_t vertex_count = 0;
  double penetration_below_0mm = 0;  // Share of vertices with signed distance < 0.
  double penetration_below_1mm = 0;  // Share with signed distance < 1 mm.
  double strain_mean = 0;            // |l / l0 - 1| over the edges.
  double strain_p99 = 0;
  double strain_max = 0;
  // Over the edges, l / l0 - 1 where an edge is longer than at rest (0 elsewhere): the cloth
  // itself stretched.
  double stretch_p99 = 0;
  // Over the edges, 1 - l / l0 where an edge is shorter than at rest (0 elsewhere): cloth
  // gathered into wrinkles finer than the mesh.
  double compression_p99 = 0;
  bool overstretched = false;  // stretch_p99 over kOverstretchStrain.
  double ease_mean_mm = 0;  // Signed garment-to-body distance.
  double ease_p50_mm = 0;
  double ease_p95_mm = 0;
  std::vector<RegionEase> region_ease;  // Regions the garment covers, in BodyRegion order.
};

// positions: the garment, V x 3 (m); edges and their rest lengths; body: the BVH of the body
// it sits on; regions: per vertex, the body region (empty: no per-region figures).
// Vertices farther than `ease_search` (m) from the body count as that far away.
FitMetrics MeasureFit(const core::Positions& positions,
                      const std::vector<std::array<int32_t, 2>>& edges,
                      const Eigen::VectorXd& edge_rest, const core::TriangleBvh& body,
                      const std::vector<body::BodyRegion>& regions, double ease_search = 0.5);

// Where a garment's supports sit on a body, by its landmarks (body::BodyLandmarks), m along
// +y; empty where the garment has no such opening.
struct SupportHeights {
  std::optional<double> waistband_above_navel;  // Waistband openings' mean height (trousers).
  // The same height as a share of the way from the crotch (0) up to the navel (1): where the
  // band sits on a torso of any length, which the height in meters does not say (a band 11 cm
  // under the navel of the mean woman sits 14 cm under it on a torso 28% longer).
  std::optional<double> waistband_crotch_to_navel;
  std::optional<double> collar_above_neck_base;  // Collars' mean height (tops).
  // Openings below the crotch that are not a piece's highest (a shoe's): trouser legs' hems.
  std::optional<double> hem_above_ankle;
};

// The rise of an avatar body (13,380 x 3, m): crotch to navel height, m. A waistband's place is
// measured on it (MeasureSupports) and held on it (ClothSettings::waistband_on_rise).
double Rise(const core::Positions& avatar);

// model: the garment's cloth model; supports: FindSupports of it; mean_body: the body avatar
// the template sits on (13,380 x 3, m), which tells leg hems from other openings; positions:
// the garment (V x 3, m) on `body` (13,380 x 3, m).
SupportHeights MeasureSupports(const ClothModel& model, const Supports& supports,
                               const core::Positions& mean_body, const core::Positions& positions,
                               const core::Positions& body);

// The q-quantile (0..1) of `values` by nearest rank; 0 for none.
double Quantile(std::vector<double> values, double q);

}  // namespace fitbase::workers

#endif  // FITBASE_WORKERS_FIT_METRICS_H_
