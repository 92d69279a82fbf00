#include "workers/fit_metrics.h"

#include "gtest/gtest.h"
#include "workers/test_shapes.h"

namespace fitbase::workers {
namespace {

core::TriangleBvh SphereBvh(double radius) {
  const core::Mesh sphere = UvSphere(radius, 48, 96);
  auto bvh = core::TriangleBvh::Build(sphere.positions, core::Triangulate(sphere.faces));
  EXPECT_TRUE(bvh.ok());
  return *std::move(bvh);
}

TEST(FitMetricsTest, PenetrationEaseAndStrain) {
  const core::TriangleBvh body = SphereBvh(0.5);
  // Four points on the +x axis at -5, 0.5, 2 and 10 mm from the (faceted) sphere.
  core::Positions p(4, 3);
  p << 0.495, 0, 0, 0.5005, 0, 0, 0.502, 0, 0, 0.51, 0, 0;
  const std::vector<std::array<int32_t, 2>> edges = {{0, 1}, {2, 3}};
  Eigen::VectorXd rest(2);
  rest << 0.0055, 0.004;  // Strains 0 and 1.0 (0.008 long).
  const FitMetrics m = MeasureFit(p, edges, rest, body,
                                  {body::BodyRegion::kTorso, body::BodyRegion::kTorso,
                                   body::BodyRegion::kArms, body::BodyRegion::kArms});
  EXPECT_DOUBLE_EQ(m.penetration_below_0mm, 0.25);
  EXPECT_DOUBLE_EQ(m.penetration_below_1mm, 0.5);
  EXPECT_NEAR(m.strain_mean, 0.5, 1e-9);
  EXPECT_NEAR(m.strain_max, 1.0, 1e-9);
  EXPECT_NEAR(m.stretch_p99, 1.0, 1e-9);
  EXPECT_NEAR(m.compression_p99, 0, 1e-9);
  EXPECT_TRUE(m.overstretched);  // p99 of {0, 1} is 1.
  EXPECT_NEAR(m.ease_mean_mm, (-5 + 0.5 + 2 + 10) / 4.0, 0.05);
  ASSERT_EQ(m.region_ease.size(), 2u);
  EXPECT_EQ(m.region_ease[1].region, body::BodyRegion::kArms);
  EXPECT_NEAR(m.region_ease[1].mean_mm, 6.0, 0.05);
}

TEST(FitMetricsTest, GatheredClothIsStrainButNotStretch) {
  const core::TriangleBvh body = SphereBvh(0.5);
  core::Positions p(3, 3);
  p << 0.51, 0, 0, 0.52, 0, 0, 0.53, 0, 0;
  const std::vector<std::array<int32_t, 2>> edges = {{0, 1}, {1, 2}};
  Eigen::VectorXd rest(2);
  rest << 0.0125, 0.02;  // Both 0.01 long: compressed by 20% and 50%.
  const FitMetrics m = MeasureFit(p, edges, rest, body, {});
  EXPECT_NEAR(m.strain_mean, 0.35, 1e-9);
  EXPECT_NEAR(m.strain_p99, 0.5, 1e-9);
  EXPECT_NEAR(m.compression_p99, 0.5, 1e-9);
  EXPECT_DOUBLE_EQ(m.stretch_p99, 0);
  EXPECT_FALSE(m.overstretched);
}

TEST(FitMetricsTest, QuantileByNearestRank) {
  std::vector<double> values = {5, 1, 4, 2, 3};
  EXPECT_EQ(Quantile(values, 0.0), 1);
  EXPECT_EQ(Quantile(values, 0.5), 3);
  EXPECT_EQ(Quantile(values, 0.99), 5);
  EXPECT_EQ(Quantile({}, 0.5), 0);
}

}  // namespace
}  // namespace fitbase::workers
