#ifndef FITBASE_WORKERS_SIZE_GRADING_H_
#define FITBASE_WORKERS_SIZE_GRADING_H_

#include <array>
#include <vector>

#include "Eigen/Core"
#include "core/mesh.h"

namespace fitbase::workers {

// Industry grading rules of thumb: each size step adds about 5% girth and 2% length.
struct GradingRates {
  double girth = 1.05;
  double length = 1.02;
};

// Rest lengths of `pairs` for the size `step` steps from the template's (M = 0, L = 1, S = -1).
// Each pair's template vector is split into its part along the local length axis (the body
// bone the garment covers there: vertical on the torso and legs, along the arm on sleeves),
// scaled by length^step, and the rest (girth around that axis), scaled by girth^step.
// template_positions, length_axes: V x 3 (m, unit vectors).
Eigen::VectorXd GradedRestLengths(const core::Positions& template_positions,
                                  const core::Positions& length_axes,
                                  const std::vector<std::array<int32_t, 2>>& pairs, int step,
                                  const GradingRates& rates = {});

}  // namespace fitbase::workers

#endif  // FITBASE_WORKERS_SIZE_GRADING_H_
