#ifndef FITBASE_WORKERS_DRAPE_H_
#define FITBASE_WORKERS_DRAPE_H_

#include <vector>

#include "Eigen/Core"
#include "absl/status/statusor.h"
#include "body/body_skeleton.h"
#include "core/mesh.h"
#include "workers/cloth_model.h"
#include "workers/cloth_solver.h"
#include "workers/fit_metrics.h"

namespace fitbase::workers {

// The fixed schedule every drape follows, whatever the body, so that drapes vary smoothly
// with the body: the body moves from the mean avatar to the target in `homotopy_steps` equal
// steps (each of at most ClothSettings::path_newton_iterations Newton iterations), then stays
// while the garment relaxes for `relax_steps`, each solved to its minimum
// (ClothSettings::newton_tolerance); the step count never depends on convergence,
// which is measured, not used to stop early (stopping the schedule when the garment comes to
// rest makes results jump between nearby bodies).
struct DrapeSchedule {
  int homotopy_steps = 20;
  int relax_steps = 5;
};

struct DrapeInput {
  const ClothModel* model = nullptr;
  core::Positions start;       // The garment on the mean avatar (the template), V x 3, m.
  Eigen::VectorXd edge_rest;   // Per model->edges: the size's rest lengths, m.
  Eigen::VectorXd hinge_rest;  // Per model->hinges: the size's rest bending angles, rad.
  Supports supports;  // Its waistbands and collars (FindSupports).
  std::vector<body::BodyRegion> regions;  // Per garment vertex, for the report (may be empty).
  core::Positions mean_body;   // 13,380 x 3, m: the body the template sits on.
  core::Positions target_body; // Same topology, m.
  core::Triangles body_triangles;
};

struct DrapeResult {
  core::Positions positions;  // V x 3, m, the template's vertex order.
  FitMetrics metrics;
  double converged_max_move_mm = 0;  // Largest vertex move over the last relaxation step.
  int steps = 0;
  double seconds = 0;  // Wall time of the simulation.
  // The size's girth on the target body were the cloth carried with the skin, over its own
  // (ClothSolver::CarriedGirthRatio; over 1: too small), and how many times firmer the ties and
  // supports were for it (TightTieFactor; 1 with friction, which replaces the ties).
  double carried_girth_ratio = 0;
  double tie_factor = 1;
};

// Drapes the garment onto input.target_body. Errors: mismatched sizes, non-finite bodies.
absl::StatusOr<DrapeResult> Drape(const DrapeInput& input, const ClothSettings& settings = {},
                                  const DrapeSchedule& schedule = {});

}  // namespace fitbase::workers

#endif  // FITBASE_WORKERS_DRAPE_H_
