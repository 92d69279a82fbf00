#include "workers/size_grading.h"

#include <cmath>

namespace fitbase::workers {

Eigen::VectorXd GradedRestLengths(const core::Positions& template_positions,
                                  const core::Positions& length_axes,
                                  const std::vector<std::array<int32_t, 2>>& pairs, int step,
                                  const GradingRates& rates) {
  const double girth = std::pow(rates.girth, step);
  const double length = std::pow(rates.length, step);
  Eigen::VectorXd rest(static_cast<Eigen::Index>(pairs.size()));
  for (size_t e = 0; e < pairs.size(); ++e) {
    const auto [i, j] = pairs[e];
    const Eigen::Vector3d d = (template_positions.row(i) - template_positions.row(j)).transpose();
    Eigen::Vector3d axis = (length_axes.row(i) + length_axes.row(j)).transpose();
    // Opposite axes (a seam between left and right) or none: treat the pair as girth only.
    const double axis_norm = axis.norm();
    const double along = axis_norm > 1e-9 ? d.dot(axis / axis_norm) : 0.0;
    const double across = std::sqrt(std::max(0.0, d.squaredNorm() - along * along));
    rest(static_cast<Eigen::Index>(e)) = std::hypot(length * along, girth * across);
  }
  return rest;
}

}  // namespace fitbase::workers
