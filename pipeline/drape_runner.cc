#include "pipeline/drape_runner.h"

#include <atomic>
#include <iostream>
#include <mutex>

#include "absl/strings/str_cat.h"
#include "core/parallel_for.h"
#include "pipeline/progress_reporter.h"
#include "proto/message_file.h"

namespace fitbase::pipeline {
namespace {

std::filesystem::path CachePath(const DrapeRunOptions& options, const std::string& key) {
  return options.cache_dir / (key + ".fbd");
}

}  // namespace

absl::StatusOr<std::vector<v1::DrapeResult>> RunDrapeTasks(
    const std::vector<const workers::DrapeTask*>& tasks, const DrapeRunOptions& options) {
  std::vector<v1::DrapeResult> results(tasks.size());
  std::vector<size_t> pending;
  for (size_t i = 0; i < tasks.size(); ++i) {
    if (!options.cache_dir.empty() &&
        proto::ReadMessageFile(CachePath(options, tasks[i]->key), &results[i]).ok() &&
        results[i].key() == tasks[i]->key) {
      continue;
    }
    pending.push_back(i);
  }
  if (!options.cache_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(options.cache_dir, ec);
    if (ec) {
      return absl::UnavailableError(absl::StrCat("cannot create drape cache ",
                                                 options.cache_dir.string(), ": ", ec.message()));
    }
  }
  std::atomic<bool> failed{false};
  std::mutex mutex;
  absl::Status first_error;
  int64_t done = static_cast<int64_t>(tasks.size() - pending.size());
  ProgressReporter progress(options.label, static_cast<int64_t>(tasks.size()), std::cerr,
                            StderrIsTerminal());
  progress.Resume(done);
  // After the first error the remaining drapes are skipped, not run: the call fails anyway.
  core::ParallelFor(pending.size(), options.jobs, [&](size_t p) {
    if (failed) return;
    const workers::DrapeTask& task = *tasks[pending[p]];
    absl::StatusOr<v1::DrapeResult> result = workers::RunDrapeTask(task);
    absl::Status status = result.status();
    if (status.ok() && !options.cache_dir.empty()) {
      status = proto::WriteMessageFile(CachePath(options, task.key), *result);
    }
    std::lock_guard<std::mutex> lock(mutex);
    if (!status.ok()) {
      if (!failed.exchange(true)) {
        first_error =
            absl::Status(status.code(), absl::StrCat("drape ", task.key, ": ", status.message()));
      }
      return;
    }
    results[pending[p]] = *std::move(result);
    progress.Update(++done);
  });
  if (failed) return first_error;
  progress.Finish();
  return results;
}

}  // namespace fitbase::pipeline
