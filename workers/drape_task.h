#ifndef FITBASE_WORKERS_DRAPE_TASK_H_
#define FITBASE_WORKERS_DRAPE_TASK_H_

#include <string>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "core/mesh.h"
#include "fitbase/v1/clothing_basis.pb.h"
#include "fitbase/v1/garment.pb.h"
#include "workers/cloth_solver.h"
#include "workers/drape.h"

namespace fitbase::workers {

// One drape as a unit of offline work, content-addressed like a Remote Execution action: its
// key hashes everything that determines the result, so equal keys mean equal results and a
// stored result can stand in for a rerun.
struct DrapeTask {
  const v1::Garment* garment = nullptr;
  std::string size;
  // The target body, 13,380 x 3, m. Rounded to float32 by MakeDrapeTask: the key hashes the
  // float32 positions, so the drape must see exactly those.
  core::Positions body;
  ClothSettings settings;
  DrapeSchedule schedule;
  std::string key;
};

// The simulator's version and settings as recorded in provenance and hashed into keys. The
// version changes whenever the solver's results change for the same inputs.
std::string SimulatorDescription(const ClothSettings& settings, const DrapeSchedule& schedule);

DrapeTask MakeDrapeTask(const v1::Garment& garment, absl::string_view size,
                        const core::Positions& body, const ClothSettings& settings = {},
                        const DrapeSchedule& schedule = {});

// Drapes the task and packs the result (float32 positions, the report) under its key.
absl::StatusOr<v1::DrapeResult> RunDrapeTask(const DrapeTask& task);

// The positions of a stored result, V x 3 (m); InvalidArgument when they are not V x 3 or
// not finite.
absl::StatusOr<core::Positions> DrapeResultPositions(const v1::DrapeResult& result,
                                                     int64_t vertex_count);

}  // namespace fitbase::workers

#endif  // FITBASE_WORKERS_DRAPE_TASK_H_
