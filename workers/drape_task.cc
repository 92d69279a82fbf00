#include "workers/drape_task.h"

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "core/content_hash.h"
#include "core/status_macros.h"
#include "workers/garment_drape.h"

namespace fitbase::workers {

std::string SimulatorDescription(const ClothSettings& s, const DrapeSchedule& schedule) {
  std::string description = absl::StrFormat(
      "%s step=%.17g newton=%d tolerance=%.17g path_newton=%d gravity=%.17g density=%.17g "
      "stretch=%.17g compression=%.17g area_floor=%.17g bending=%.17g anchor=%.17g tie=%.17g "
      "friction=%.17g grip=%.17g band_stiffness=%.17g band_anchor=%.17g band_on_rise=%d "
      "contact=%.17g offset=%.17g search=%.17g factorization=%s homotopy=%d relax=%d",
      kSimulatorVersion, s.step_seconds, s.newton_iterations, s.newton_tolerance,
      s.path_newton_iterations, s.gravity, s.areal_density, s.stretch_stiffness,
      s.compression_stiffness, s.area_floor, s.bending_rigidity, s.anchor_stiffness, s.skin_tie,
      s.friction, s.waistband_grip, s.waistband_stiffness, s.waistband_anchor_stiffness,
      s.waistband_on_rise ? 1 : 0, s.contact_stiffness, s.collision_offset, s.collision_search,
      s.factorization == Factorization::kSimplicialLdlt ? "simplicial" : "supernodal",
      schedule.homotopy_steps, schedule.relax_steps);
  // Only where set, so the keys of drapes made before it stay good: without it they are the same.
  if (s.cuff_friction > 0) {
    absl::StrAppendFormat(&description, " cuff_friction=%.17g", s.cuff_friction);
  }
  return description;
}

DrapeTask MakeDrapeTask(const v1::Garment& garment, absl::string_view size,
                        const core::Positions& body, const ClothSettings& settings,
                        const DrapeSchedule& schedule) {
  DrapeTask task{&garment, std::string(size), body.cast<float>().cast<double>(), settings,
                 schedule, ""};
  const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor> body32 = body.cast<float>();
  core::ContentHash hash;
  hash.Add(absl::string_view("drape"))
      .Add(absl::string_view(garment.id()))
      .Add(absl::string_view(task.size))
      .Add(absl::string_view(SimulatorDescription(settings, schedule)))
      .Add(std::span<const float>(body32.data(), static_cast<size_t>(body32.size())));
  task.key = hash.HexDigest();
  return task;
}

absl::StatusOr<v1::DrapeResult> RunDrapeTask(const DrapeTask& task) {
  ASSIGN_OR_RETURN(GarmentFit fit,
                   DrapeGarment(*task.garment, task.size, task.body, task.settings, task.schedule));
  v1::DrapeResult result;
  result.set_key(task.key);
  auto* positions = result.mutable_positions();
  positions->Reserve(static_cast<int>(fit.positions.size()));
  for (double value : fit.positions.reshaped<Eigen::RowMajor>()) {
    positions->AddAlreadyReserved(static_cast<float>(value));
  }
  *result.mutable_report() = std::move(fit.report);
  return result;
}

absl::StatusOr<core::Positions> DrapeResultPositions(const v1::DrapeResult& result,
                                                     int64_t vertex_count) {
  if (result.positions_size() != 3 * vertex_count) {
    return absl::InvalidArgumentError(absl::StrCat("drape result ", result.key(), " has ",
                                                   result.positions_size(),
                                                   " coordinates; expected ", 3 * vertex_count));
  }
  const core::Positions positions =
      Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>>(
          result.positions().data(), vertex_count, 3)
          .cast<double>();
  if (!positions.allFinite()) {
    return absl::InvalidArgumentError(
        absl::StrCat("drape result ", result.key(), " has non-finite positions"));
  }
  return positions;
}

}  // namespace fitbase::workers
