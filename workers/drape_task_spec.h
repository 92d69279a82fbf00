#ifndef FITBASE_WORKERS_DRAPE_TASK_SPEC_H_
#define FITBASE_WORKERS_DRAPE_TASK_SPEC_H_

#include "absl/status/statusor.h"
#include "fitbase/v1/build.pb.h"
#include "workers/cloth_solver.h"
#include "workers/drape.h"
#include "workers/drape_task.h"

namespace fitbase::workers {

// A drape task on the wire (coordinator to worker) and back.

v1::DrapeSettings DrapeSettingsToProto(const ClothSettings& settings,
                                       const DrapeSchedule& schedule);

// INVALID_ARGUMENT naming the field when a setting is not finite or out of its range.
absl::Status DrapeSettingsFromProto(const v1::DrapeSettings& proto, ClothSettings* settings,
                                    DrapeSchedule* schedule);

v1::DrapeTaskSpec DrapeTaskToSpec(const DrapeTask& task);

// The task of a spec; its garment points into `spec`, which must outlive it. The key is
// recomputed from the content, so a spec whose key does not match what it carries (a corrupt
// or forged message) is INVALID_ARGUMENT rather than a result stored under the wrong key.
absl::StatusOr<DrapeTask> DrapeTaskFromSpec(const v1::DrapeTaskSpec& spec);

}  // namespace fitbase::workers

#endif  // FITBASE_WORKERS_DRAPE_TASK_SPEC_H_
