#include "workers/fit_metrics.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "body/body_measurements.h"

namespace fitbase::workers {
namespace {

constexpr double kMmPerMeter = 1000.0;
constexpr double kMinStrainRest = 1e-6;

double Mean(const std::vector<double>& values) {
  return values.empty() ? 0.0
                        : std::accumulate(values.begin(), values.end(), 0.0) /
                              static_cast<double>(values.size());
}

}  // namespace

double Rise(const core::Positions& avatar) {
  return avatar(body::BodyLandmarks::kNavel, 1) - avatar(body::BodyLandmarks::kCrotch, 1);
}

SupportHeights MeasureSupports(const ClothModel& model, const Supports& supports,
                               const core::Positions& mean_body, const core::Positions& positions,
                               const core::Positions& body) {
  using body::BodyLandmarks;
  auto mean_height = [&](const std::vector<int32_t>& vertices) {
    double sum = 0;
    for (int32_t v : vertices) sum += positions(v, 1);
    return sum / static_cast<double>(vertices.size());
  };
  auto average = [](const std::vector<double>& values) -> std::optional<double> {
    if (values.empty()) return std::nullopt;
    return Mean(values);
  };
  const double crotch = mean_body(BodyLandmarks::kCrotch, 1);
  const double neck_base =
      0.5 * (body(BodyLandmarks::kNeckFront, 1) + body(BodyLandmarks::kNeckBack, 1));
  std::vector<double> waistbands, shares, collars, hems;
  const double rise = Rise(body);
  for (size_t o = 0; o < model.openings.size(); ++o) {
    const Opening& opening = model.openings[o];
    if (supports.IsWaistband(opening)) {
      waistbands.push_back(mean_height(opening.vertices) - body(BodyLandmarks::kNavel, 1));
      if (rise > 0) shares.push_back(1 + waistbands.back() / rise);
    }
    if (supports.IsCollar(static_cast<int32_t>(o))) {
      collars.push_back(mean_height(opening.vertices) - neck_base);
    }
    if (!opening.highest_of_piece && opening.mean_height < crotch) {
      hems.push_back(mean_height(opening.vertices) - body(BodyLandmarks::kLeftAnkle, 1));
    }
  }
  return {average(waistbands), average(shares), average(collars), average(hems)};
}

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const double n = static_cast<double>(values.size());
  const size_t rank =
      std::min(values.size() - 1, q <= 0 ? size_t{0} : static_cast<size_t>(std::ceil(q * n)) - 1);
  std::nth_element(values.begin(), values.begin() + static_cast<ptrdiff_t>(rank), values.end());
  return values[rank];
}

FitMetrics MeasureFit(const core::Positions& positions,
                      const std::vector<std::array<int32_t, 2>>& edges,
                      const Eigen::VectorXd& edge_rest, const core::TriangleBvh& body,
                      const std::vector<body::BodyRegion>& regions, double ease_search) {
  FitMetrics m;
  const Eigen::Index n = positions.rows();
  m.vertex_count = n;
  std::vector<double> ease(static_cast<size_t>(n));
  std::array<std::vector<double>, body::kBodyRegionCount> by_region;
  int64_t below_0 = 0, below_1 = 0;
  for (Eigen::Index v = 0; v < n; ++v) {
    const core::SurfacePoint hit = body.Closest(positions.row(v).transpose(), ease_search);
    const double mm = kMmPerMeter * (hit.found ? hit.signed_distance : ease_search);
    ease[v] = mm;
    below_0 += mm < 0.0;
    below_1 += mm < 1.0;
    if (!regions.empty()) by_region[static_cast<int>(regions[v])].push_back(mm);
  }
  m.penetration_below_0mm = static_cast<double>(below_0) / static_cast<double>(n);
  m.penetration_below_1mm = static_cast<double>(below_1) / static_cast<double>(n);
  m.ease_mean_mm = Mean(ease);
  m.ease_p50_mm = Quantile(ease, 0.5);
  m.ease_p95_mm = Quantile(ease, 0.95);
  for (int r = 0; r < body::kBodyRegionCount; ++r) {
    if (by_region[r].empty()) continue;
    m.region_ease.push_back({static_cast<body::BodyRegion>(r),
                             static_cast<int64_t>(by_region[r].size()), Mean(by_region[r]),
                             Quantile(by_region[r], 0.95)});
  }
  std::vector<double> strain, stretch, compression;
  strain.reserve(edges.size());
  stretch.reserve(edges.size());
  compression.reserve(edges.size());
  for (size_t e = 0; e < edges.size(); ++e) {
    const double rest = edge_rest(static_cast<Eigen::Index>(e));
    // A weld (two coincident seam vertices) has no strain to speak of.
    if (rest < kMinStrainRest) continue;
    const double length = (positions.row(edges[e][0]) - positions.row(edges[e][1])).norm();
    const double change = length / rest - 1.0;
    strain.push_back(std::abs(change));
    stretch.push_back(std::max(change, 0.0));
    compression.push_back(std::max(-change, 0.0));
  }
  m.strain_mean = Mean(strain);
  m.strain_p99 = Quantile(strain, 0.99);
  m.strain_max = strain.empty() ? 0.0 : *std::max_element(strain.begin(), strain.end());
  m.stretch_p99 = Quantile(stretch, 0.99);
  m.compression_p99 = Quantile(compression, 0.99);
  m.overstretched = m.stretch_p99 > kOverstretchStrain;
  return m;
}

}  // namespace fitbase::workers
