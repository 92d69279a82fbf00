#ifndef FITBASE_PIPELINE_DRAPE_RUNNER_H_
#define FITBASE_PIPELINE_DRAPE_RUNNER_H_

#include <filesystem>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fitbase/v1/clothing_basis.pb.h"
#include "workers/drape_task.h"

namespace fitbase::pipeline {

struct DrapeRunOptions {
  // Results are stored as <key>.fbd here and reused when present (empty: no cache). Keys hash
  // every input of a drape, so a stored result is the result.
  std::filesystem::path cache_dir;
  int jobs = 1;               // Drapes run side by side, each single-threaded.
  std::string label = "drapes";  // For the progress line on stderr.
};

// Runs every task (or takes it from the cache) and returns the results in task order. The
// first failing drape fails the run with its key in the message; the others stop early.
absl::StatusOr<std::vector<v1::DrapeResult>> RunDrapeTasks(
    const std::vector<const workers::DrapeTask*>& tasks, const DrapeRunOptions& options);

}  // namespace fitbase::pipeline

#endif  // FITBASE_PIPELINE_DRAPE_RUNNER_H_
