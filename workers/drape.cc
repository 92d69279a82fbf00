#include "workers/drape.h"

#include <chrono>

#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "core/triangle_bvh.h"
#include "workers/garment_template.h"

namespace fitbase::workers {
namespace {

constexpr double kMmPerMeter = 1000.0;
// Rounds of putting vertices and triangles clear of the body at the end: a lifted triangle may
// carry a corner into a crease, and a pushed vertex may tilt a triangle onto the skin.
constexpr int kClearancePasses = 4;

absl::Status ValidateInput(const DrapeInput& in) {
  if (in.model == nullptr) return absl::InvalidArgumentError("drape has no cloth model");
  const Eigen::Index n = in.model->inverse_masses.size();
  if (in.start.rows() != n) {
    return absl::InvalidArgumentError(
        absl::StrCat("garment start has ", in.start.rows(), " vertices, model ", n));
  }
  if (in.edge_rest.size() != static_cast<Eigen::Index>(in.model->edges.size()) ||
      in.hinge_rest.size() != static_cast<Eigen::Index>(in.model->hinges.size())) {
    return absl::InvalidArgumentError("rest shape does not match the garment's constraints");
  }
  // Zero is allowed: garments weld coincident seam vertices with zero-length edges.
  if (!(in.edge_rest.array() >= 0).all() || !in.edge_rest.allFinite()) {
    return absl::InvalidArgumentError("rest lengths must be non-negative and finite");
  }
  if (!(in.hinge_rest.array().abs() <= M_PI).all()) {
    return absl::InvalidArgumentError("rest bending angles must be finite, within [-pi, pi]");
  }
  if (in.target_body.rows() != in.mean_body.rows()) {
    return absl::InvalidArgumentError(absl::StrCat("target body has ", in.target_body.rows(),
                                                   " vertices; the garment's mean avatar has ",
                                                   in.mean_body.rows()));
  }
  if (!in.target_body.allFinite() || !in.mean_body.allFinite() || !in.start.allFinite()) {
    return absl::InvalidArgumentError("drape input has non-finite positions");
  }
  auto ascending_below = [](const std::vector<int32_t>& indices, size_t count) {
    for (size_t i = 0; i < indices.size(); ++i) {
      if (indices[i] < 0 || static_cast<size_t>(indices[i]) >= count ||
          (i > 0 && indices[i] <= indices[i - 1])) {
        return false;
      }
    }
    return true;
  };
  if (!ascending_below(in.supports.waistband_edges, in.model->edges.size())) {
    return absl::InvalidArgumentError(
        "waistband edges must be ascending indices of the garment's edges");
  }
  if (!ascending_below(in.supports.collars, in.model->openings.size())) {
    return absl::InvalidArgumentError(
        "collars must be ascending indices of the garment's openings");
  }
  if (!ascending_below(in.supports.straps, in.model->openings.size())) {
    return absl::InvalidArgumentError(
        "straps must be ascending indices of the garment's openings");
  }
  if (!ascending_below(in.supports.cuffs, in.model->openings.size())) {
    return absl::InvalidArgumentError("cuffs must be ascending indices of the garment's openings");
  }
  if (!in.regions.empty() && static_cast<Eigen::Index>(in.regions.size()) != n) {
    return absl::InvalidArgumentError("garment regions do not match its vertices");
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<DrapeResult> Drape(const DrapeInput& in, const ClothSettings& settings,
                                  const DrapeSchedule& schedule) {
  RETURN_IF_ERROR(ValidateInput(in));
  const auto start_time = std::chrono::steady_clock::now();
  ASSIGN_OR_RETURN(core::TriangleBvh body, core::TriangleBvh::Build(in.mean_body, in.body_triangles));
  ClothSolver solver(*in.model, in.start, in.edge_rest, in.hinge_rest, in.supports, body,
                     settings);
  DrapeResult result;
  result.carried_girth_ratio = solver.CarriedGirthRatio(in.target_body, in.body_triangles);
  if (settings.friction == 0) {
    result.tie_factor = TightTieFactor(settings, result.carried_girth_ratio);
    solver.FirmTies(result.tie_factor);
  }
  for (int step = 1; step <= schedule.homotopy_steps; ++step) {
    const double t = static_cast<double>(step) / schedule.homotopy_steps;
    body.Refit((1.0 - t) * in.mean_body + t * in.target_body);
    solver.Step(body);
  }
  if (schedule.homotopy_steps == 0) body.Refit(in.target_body);
  double last_move = 0;
  for (int step = 0; step < schedule.relax_steps; ++step) last_move = solver.Step(body);
  // Contact is a penalty, so a triangle pressed into the skin between its corners is lifted
  // clear, and a vertex pressed hard may sit a little inside the offset; one deep enough to
  // count as penetrating is put back on it. Vertices go last: a triangle lifted off one body
  // part in a crease may carry a corner into the other.
  int moved = 1;
  for (int pass = 0; pass < kClearancePasses && moved > 0; ++pass) {
    moved = solver.ClearTriangles(body);
    moved += solver.ResolveCollisions(body, kTemplatePushSearch, kPenetrationDistance);
  }
  result.positions = solver.positions();
  result.steps = schedule.homotopy_steps + schedule.relax_steps;
  result.converged_max_move_mm = kMmPerMeter * last_move;
  result.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  result.metrics = MeasureFit(result.positions, in.model->edges, in.edge_rest, body, in.regions);
  return result;
}

}  // namespace fitbase::workers
