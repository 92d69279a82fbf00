#ifndef FITBASE_PIPELINE_PROGRESS_REPORTER_H_
#define FITBASE_PIPELINE_PROGRESS_REPORTER_H_

#include <chrono>
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>

namespace fitbase::pipeline {

// A one-line progress display for long commands: "label  done/total  elapsed  ETA".
// On a terminal the line is redrawn in place; otherwise a line is printed at most once a
// minute and at the end, so logs of long runs show progress and stay readable. The clock is
// injected so tests can drive time.
class ProgressReporter {
 public:
  using Clock = std::function<std::chrono::steady_clock::time_point()>;

  ProgressReporter(std::string label, int64_t total, std::ostream& out, bool is_terminal,
                   Clock clock = std::chrono::steady_clock::now);

  // Records items finished before this reporter started (found in a cache, or done before a
  // watch joined): they count in done/total but not in the rate the ETA comes from, which
  // would otherwise promise the rest at the speed of a cache read.
  void Resume(int64_t done);
  // Records that `done` items of `total` are finished.
  void Update(int64_t done);
  // Prints the final line (always, terminal or not).
  void Finish();

  // The current line, without carriage return or newline.
  std::string Line() const;

 private:
  std::string label_;
  int64_t total_;
  int64_t done_ = 0;
  int64_t done_at_start_ = 0;
  std::ostream& out_;
  bool is_terminal_;
  Clock clock_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

// True when stderr is a terminal.
bool StderrIsTerminal();

}  // namespace fitbase::pipeline

#endif  // FITBASE_PIPELINE_PROGRESS_REPORTER_H_
